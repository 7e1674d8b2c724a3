#include "haptic_loop.hpp"

#include <utility>

#include "session/scripted_hand.hpp"

namespace cathbox::bench {

bool HapticLoop::ensure_running(std::string& error) {
  if (session_ && !session_->over()) return true;
  retire();
  session::SessionCaseLoad scene = session::load_session_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.case");
  if (!scene) return (error = scene.error().message), false;
  session::SessionOptions options;
  options.end_at_target = false;
  // A hand that never ends its run: no time limit, no end of the path (it keeps pushing, backing
  // off and trying again there, the contact-heavy case), never gives up.
  session::ScriptedHandSettings settings;
  settings.time_limit_s = 1e9;
  settings.end_margin_mm = -1.0;
  settings.max_fruitless_retries = 1 << 30;
  auto hand = std::make_unique<session::ScriptedHand>(scene.value()->route_mm, scene.value()->spec.tools.front().length_mm(), settings);
  hand->set_tick_s(static_cast<double>(options.period_us) * 1e-6);
  session_ = std::make_unique<session::Session>(std::move(scene.value()), std::move(hand), options);
  session_->start();
  ++starts_;
  return true;
}

void HapticLoop::retire() {
  if (!session_) return;
  scheduling_ = session_->haptic_scheduling();
  session_->stop();
  ticks_done_ += session_->ticks();
  dropped_done_ += session_->dropped_ticks();
  cpu_done_us_ += session_->haptic_cpu_time_us();
  session_.reset();
}

HapticLoop& haptic() {
  static HapticLoop loop;
  return loop;
}

HapticWindow::HapticWindow(benchmark::State& state) {
  std::string error;
  if (!haptic().ensure_running(error)) state.SkipWithError(("haptic loop: " + error).c_str());
  ticks0_ = haptic().ticks();
  dropped0_ = haptic().dropped();
  cpu0_us_ = haptic().cpu_us();
  starts0_ = haptic().starts();
  t0_ = std::chrono::steady_clock::now();
}

void HapticWindow::keep(benchmark::State& state) {
  std::string error;
  if (!haptic().ensure_running(error)) state.SkipWithError(("haptic loop: " + error).c_str());
}

void HapticWindow::report(benchmark::State& state) const {
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0_).count();
  state.counters["haptic_dropped"] = static_cast<double>(haptic().dropped() - dropped0_);
  state.counters["haptic_hz"] = s > 0.0 ? static_cast<double>(haptic().ticks() - ticks0_) / s : 0.0;
  state.counters["haptic_restarts"] = haptic().starts() - starts0_;
  state.counters["haptic_cpu_share"] = s > 0.0 ? static_cast<double>(haptic().cpu_us() - cpu0_us_) * 1e-6 / s : 0.0;
}

}  // namespace cathbox::bench
