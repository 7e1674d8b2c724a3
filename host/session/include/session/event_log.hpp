#pragma once
// Messages for the output panel (contacts, faults, device events), passed from the haptic
// thread to the render thread through a fixed-size single-producer single-consumer ring: the
// producer never blocks and never allocates; when the ring is full the message is counted as
// lost instead.
#include <array>
#include <atomic>
#include <cstdint>
#include <string>

namespace cathbox::session {

struct LogEvent {
  std::int64_t time_us = 0;
  std::array<char, 112> text{};
};

class EventLog {
 public:
  static constexpr std::size_t kCapacity = 256;

  // Producer (one thread). Text longer than the slot is cut.
  bool push(std::int64_t time_us, const char* text);
  // Consumer (one other thread).
  bool pop(LogEvent& out);
  [[nodiscard]] std::uint64_t lost() const { return lost_.load(std::memory_order_relaxed); }

 private:
  std::array<LogEvent, kCapacity> ring_{};
  std::atomic<std::uint64_t> head_{0};  // next slot to write
  std::atomic<std::uint64_t> tail_{0};  // next slot to read
  std::atomic<std::uint64_t> lost_{0};
};

}  // namespace cathbox::session
