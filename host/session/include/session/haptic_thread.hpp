#pragma once
// The haptic loop's thread: runs a tick function at a fixed rate (1 kHz by default) against a
// Clock, measures the achieved rate, and counts ticks dropped after stalls. The tick function
// receives the simulation time (ticks x period) and returns false to end the run; the idle
// function, if any, runs in the wait after them.
#include <atomic>
#include <cstdint>
#include <functional>
#include <optional>
#include "base/jthread.hpp"

#include "session/clock.hpp"
#include "session/haptic_pacer.hpp"
#include "session/rate_meter.hpp"
#include "session/thread_priority.hpp"

namespace cathbox::session {

class HapticThread {
 public:
  using TickFn = std::function<bool(std::int64_t sim_time_us)>;
  // Work for the next tick done ahead of it (Simulator::prepare_next_step): run once after the
  // ticks that were due, before the loop sleeps, when half a period or more is left before the
  // next tick. Never while late.
  using IdleFn = std::function<void()>;

  HapticThread(Clock& clock, std::int64_t period_us, TickFn tick, IdleFn idle = {});
  ~HapticThread();
  HapticThread(const HapticThread&) = delete;
  HapticThread& operator=(const HapticThread&) = delete;

  void start();
  // Requests the stop and joins.
  void stop();
  // Runs the loop on the calling thread until the tick function returns false, the stop token
  // fires, or `max_ticks` ticks in total have run (negative: no limit). Successive calls carry
  // on where the last one stopped (headless frames step the loop this way in virtual time).
  void run(base::stop_token stop, std::int64_t max_ticks = -1);

  [[nodiscard]] bool finished() const { return finished_.load(std::memory_order_acquire); }
  [[nodiscard]] std::int64_t ticks() const { return ticks_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::int64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }
  // Ticks per second of clock time, over the last half second.
  [[nodiscard]] double rate_hz() const { return rate_hz_.load(std::memory_order_relaxed); }
  // CPU time the loop's thread has used (updated every 100 ticks).
  [[nodiscard]] std::int64_t cpu_time_us() const { return cpu_us_.load(std::memory_order_relaxed); }
  // The scheduling the started thread obtained (kNormal before start()).
  [[nodiscard]] HapticScheduling scheduling() const { return scheduling_.load(std::memory_order_relaxed); }

 private:
  Clock& clock_;
  std::int64_t period_us_;
  TickFn tick_;
  IdleFn idle_;
  bool idle_due_ = false;  // ticks ran since the idle work last did
  std::optional<HapticPacer> pacer_;
  bool idle_after(std::int64_t now_us);  // the idle work, if due and time allows; true: it ran
  RateMeter meter_;
  base::jthread thread_;
  std::atomic<bool> finished_{false};
  std::atomic<std::int64_t> ticks_{0};
  std::atomic<std::int64_t> dropped_{0};
  std::atomic<double> rate_hz_{0.0};
  std::atomic<std::int64_t> cpu_us_{0};
  std::atomic<HapticScheduling> scheduling_{HapticScheduling::kNormal};
};

}  // namespace cathbox::session
