#include "session/haptic_thread.hpp"

#include <utility>

#include "session/haptic_memory.hpp"

namespace cathbox::session {

HapticThread::HapticThread(Clock& clock, std::int64_t period_us, TickFn tick, IdleFn idle)
    : clock_(clock), period_us_(period_us), tick_(std::move(tick)), idle_(std::move(idle)) {}

HapticThread::~HapticThread() { stop(); }

void HapticThread::start() {
  if (thread_.joinable()) return;
  keep_freed_memory();
  thread_ = base::jthread([this](base::stop_token stop) {
    scheduling_.store(ThreadPriority::favour_calling_thread(), std::memory_order_relaxed);
    run(std::move(stop));
  });
}

void HapticThread::stop() {
  if (!thread_.joinable()) return;
  thread_.request_stop();
  thread_.join();
}

void HapticThread::run(base::stop_token stop, std::int64_t max_ticks) {
  if (!pacer_) pacer_.emplace(period_us_, clock_.now_us());
  HapticPacer& pacer = *pacer_;
  RateMeter& meter = meter_;
  std::int64_t n = ticks_.load(std::memory_order_relaxed);
  bool go_on = true;
  while (go_on && !stop.stop_requested() && (max_ticks < 0 || n < max_ticks)) {
    const std::int64_t now = clock_.now_us();
    const HapticPacer::Due due = pacer.due(now);
    if (due.dropped > 0) dropped_.fetch_add(due.dropped, std::memory_order_relaxed);
    for (int i = 0; i < due.ticks && go_on && (max_ticks < 0 || n < max_ticks); ++i) {
      go_on = tick_(n * period_us_);
      ++n;
      ticks_.store(n, std::memory_order_relaxed);
      meter.tick(now);
      idle_due_ = go_on;
    }
    rate_hz_.store(meter.rate_hz(), std::memory_order_relaxed);
    if (n % 100 < static_cast<std::int64_t>(due.ticks)) cpu_us_.store(thread_cpu_time_us(), std::memory_order_relaxed);
    if (due.ticks > 0) continue;
    // No tick due: the next tick's work that can be done ahead, once, with half a period or more
    // left before it, then the wait. (A tick that ran late goes straight on to the next: the
    // pacer finds it due; one that ran long leaves that work to the next tick.)
    if (idle_after(now)) continue;
    clock_.sleep_until_us(pacer.next_deadline_us());
  }
  // A run ended by its tick count (a caller stepping the loop tick by tick in virtual time, as
  // the browser's haptic worker does) does the idle work before it returns, not before the next
  // call's tick.
  if (go_on && max_ticks >= 0 && n >= max_ticks) idle_after(clock_.now_us());
  finished_.store(true, std::memory_order_release);
}

bool HapticThread::idle_after(std::int64_t now_us) {
  if (!idle_due_ || !idle_ || pacer_->next_deadline_us() - now_us < period_us_ / 2) return false;
  idle_due_ = false;
  idle_();
  return true;
}

}  // namespace cathbox::session
