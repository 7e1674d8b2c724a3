// What drives a session's ticks: the real-time haptic thread (start, stop) or virtual time
// (step_virtual), and the figures of whichever ran.
#include "session/session.hpp"

#include "session/thread_priority.hpp"

namespace cathbox::session {

const HapticThread* Session::active_thread() const {
  return real_thread_ ? real_thread_.get() : virtual_thread_.get();
}

void Session::start() {
  // Walls built on a worker, swapped in at the same ticks as in virtual time (a late build makes
  // its due tick wait: tool/wall_swap.hpp).
  if (angioplasty_) angioplasty_->swap().set_mode(tool::WallSwap::Mode::kWorker);
  if (!real_thread_) {
    real_thread_ = std::make_unique<HapticThread>(
        real_clock(), options_.period_us, [this](std::int64_t) { return tick(); }, [this] { prepare_next_tick(); });
  }
  real_thread_->start();
}

void Session::stop() {
  if (real_thread_) real_thread_->stop();
}

std::int64_t Session::step_virtual(std::int64_t ticks) {
  if (angioplasty_) angioplasty_->swap().set_mode(tool::WallSwap::Mode::kSynchronous);  // same walls at the same ticks
  if (!virtual_thread_) {
    virtual_thread_ = std::make_unique<HapticThread>(
        virtual_clock_, options_.period_us, [this](std::int64_t) { return tick(); }, [this] { prepare_next_tick(); });
  }
  const std::int64_t before = tick_;
  virtual_thread_->run(base::stop_token{}, virtual_thread_->ticks() + ticks);
  return tick_ - before;
}

void Session::prepare_next_tick() {
  if (!over_.load(std::memory_order_relaxed)) sim_->prepare_next_step();
}

device::Clock& Session::real_clock() { return options_.real_time_clock != nullptr ? *options_.real_time_clock : steady_; }

std::optional<std::int64_t> Session::real_time_drops() const {
  if (real_thread_) return real_thread_->dropped();
  const std::int64_t told = paced_drops_.load(std::memory_order_acquire);
  return told >= 0 ? std::optional<std::int64_t>(told) : std::nullopt;
}

double Session::haptic_rate_hz() const { return active_thread() ? active_thread()->rate_hz() : 0.0; }
std::int64_t Session::dropped_ticks() const { return active_thread() ? active_thread()->dropped() : 0; }
std::int64_t Session::haptic_cpu_time_us() const { return active_thread() ? active_thread()->cpu_time_us() : 0; }

std::string Session::haptic_scheduling() const {
  return real_thread_ ? ThreadPriority::name(real_thread_->scheduling()) : "virtual time";
}

}  // namespace cathbox::session
