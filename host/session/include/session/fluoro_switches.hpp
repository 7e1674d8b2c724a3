#pragma once
// The trainee's fluoroscopy switches as controls: the pedal (a key held, or a lab rig's GPIO
// foot pedal through device::FootPedal, debounced on the caller's clock), the inject key and
// the roadmap keys, and the C-arm keys (each press turns it by kCArmStep_deg from where it is).
// A front end calls update() once per frame with what is held now; a control
// is posted on each change only (pressing the pedal once, injecting once per key press), so
// the session records presses, not frames. Front-end thread; the session's post() never blocks.
#include <cstdint>
#include <functional>
#include <string>

#include "device/foot_pedal.hpp"
#include "flow/c_arm.hpp"
#include "session/control.hpp"
#include "session/fluoro_controls.hpp"

namespace cathbox::session {

struct FluoroKeys {
  bool pedal = false;          // the pedal key is held
  bool inject = false;         // the inject key is down
  bool roadmap = false;        // the roadmap key is down (capture)
  bool clear_roadmap = false;  // the clear-roadmap key is down
  bool rao = false;            // C-arm keys: towards RAO / LAO, caudal / cranial
  bool lao = false;
  bool caudal = false;
  bool cranial = false;
};

class FluoroSwitches {
 public:
  using Post = std::function<bool(const Control&)>;
  static constexpr double kCArmStep_deg = 5.0;
  // `foot_pedal` (may be null) must outlive this object. Each key press injects `inject_ml` at
  // `inject_rate_ml_s`.
  explicit FluoroSwitches(device::FootPedal* foot_pedal = nullptr, double inject_ml = 6.0,
                          double inject_rate_ml_s = 3.0);

  // What is held at now_us (the caller's clock, non-decreasing): posts the controls for what
  // changed. The pedal is down while the key or the foot pedal is. `carm`: the C-arm now (the
  // session's snapshot); without it the C-arm keys do nothing.
  void update(const FluoroKeys& keys, std::uint64_t now_us, const Post& post, const flow::CArmPose* carm = nullptr);

  // What the inject key injects from now on (the trainer's C-arm panel sets it).
  void set_injection(double volume_ml, double rate_ml_s, double concentration_mgI_ml) {
    inject_ml_ = volume_ml;
    inject_rate_ml_s_ = rate_ml_s;
    inject_mgI_ml_ = concentration_mgI_ml;
  }
  [[nodiscard]] bool pedal_down() const { return pedal_; }
  // The foot pedal's last read error (empty when it reads); its last good state is kept.
  [[nodiscard]] const std::string& pedal_error() const { return pedal_error_; }

 private:
  device::FootPedal* foot_;
  device::PedalDebouncer debouncer_;
  double inject_ml_;
  double inject_rate_ml_s_;
  double inject_mgI_ml_ = fluoro_control::kDefaultContrast_mgI_ml;
  bool pedal_ = false;
  FluoroKeys last_;
  std::string pedal_error_;
};

}  // namespace cathbox::session
