#pragma once
// The server's notion of now: microseconds since the Unix epoch. Token expiry, login
// throttling and live-rig staleness read it, so tests drive them in virtual time.
#include <atomic>
#include <cstdint>

namespace cathbox::server {

class Clock {
 public:
  virtual ~Clock() = default;
  [[nodiscard]] virtual std::int64_t now_us() = 0;
};

class SystemClock final : public Clock {
 public:
  [[nodiscard]] std::int64_t now_us() override;
};

// Virtual time for tests: starts where it is told and moves only when advanced.
class ManualClock final : public Clock {
 public:
  explicit ManualClock(std::int64_t start_us = 1'700'000'000'000'000) : now_(start_us) {}
  [[nodiscard]] std::int64_t now_us() override { return now_.load(); }
  void advance_us(std::int64_t us) { now_ += us; }

 private:
  std::atomic<std::int64_t> now_;
};

}  // namespace cathbox::server
