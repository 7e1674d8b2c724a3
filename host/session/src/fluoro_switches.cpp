#include "session/fluoro_switches.hpp"

#include "session/fluoro_controls.hpp"

namespace cathbox::session {

FluoroSwitches::FluoroSwitches(device::FootPedal* foot_pedal, double inject_ml, double inject_rate_ml_s)
    : foot_(foot_pedal), inject_ml_(inject_ml), inject_rate_ml_s_(inject_rate_ml_s) {}

void FluoroSwitches::update(const FluoroKeys& keys, std::uint64_t now_us, const Post& post, const flow::CArmPose* carm) {
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
  if (keys.inject && !last_.inject) (void)post(fluoro_control::inject(inject_ml_, inject_rate_ml_s_, inject_mgI_ml_));
  if (keys.roadmap && !last_.roadmap) (void)post(fluoro_control::roadmap(true));
  if (keys.clear_roadmap && !last_.clear_roadmap) (void)post(fluoro_control::roadmap(false));
  if (carm != nullptr) {
    // One step per press; out-of-range angles are refused (and logged) by the session.
    const auto press = [&](bool now, bool before) { return now && !before ? 1.0 : 0.0; };
    const double lao = press(keys.lao, last_.lao) - press(keys.rao, last_.rao);
    const double cranial = press(keys.cranial, last_.cranial) - press(keys.caudal, last_.caudal);
    if (lao != 0.0 || cranial != 0.0) {
      (void)post(fluoro_control::carm_angles(carm->lao_deg + lao * kCArmStep_deg, carm->cranial_deg + cranial * kCArmStep_deg));
    }
  }
  last_ = keys;
}

}  // namespace cathbox::session
