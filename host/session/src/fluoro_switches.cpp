#include "session/fluoro_switches.hpp"

#include "session/fluoro_controls.hpp"

namespace cathbox::session {

FluoroSwitches::FluoroSwitches(device::FootPedal* foot_pedal, double inject_ml, double inject_rate_ml_s)
    : foot_(foot_pedal), inject_ml_(inject_ml), inject_rate_ml_s_(inject_rate_ml_s) {}

void FluoroSwitches::update(const FluoroKeys& keys, std::uint64_t now_us, const Post& post) {
  bool foot = false;
  if (foot_ != nullptr) {
    const device::Result<bool> raw = foot_->read();
    if (raw) {
      pedal_error_.clear();
      foot = debouncer_.update(*raw, now_us);
    } else {
      pedal_error_ = raw.error().message;
      foot = debouncer_.pressed();
    }
  }
  const bool pedal = keys.pedal || foot;
  if (pedal != pedal_ && post(fluoro_control::pedal(pedal))) pedal_ = pedal;
  if (keys.inject && !last_.inject) (void)post(fluoro_control::inject(inject_ml_, inject_rate_ml_s_));
  if (keys.roadmap && !last_.roadmap) (void)post(fluoro_control::roadmap(true));
  if (keys.clear_roadmap && !last_.clear_roadmap) (void)post(fluoro_control::roadmap(false));
  last_ = keys;
}

}  // namespace cathbox::session
