#pragma once
// What the trainer's C-arm panel edits, without GL: the C-arm's angles and geometry, the pulse
// rate, the standard and the case's working projections, the injection that the panel's Inject
// button and the I key give, and the roadmap. Every edit becomes one of the session's
// fluoroscopy controls (kinds 32..37, session/fluoro_controls.hpp), so it is recorded and
// replayed like a key press; nothing here changes the session itself. The panel (carm_panel.hpp)
// draws these fields and posts what the edit functions return.
#include <optional>
#include <string>
#include <vector>

#include "flow/c_arm.hpp"
#include "session/control.hpp"
#include "session/fluoro_controls.hpp"

namespace cathbox::app {

struct InjectionSettings {
  double volume_ml = 6.0;
  double rate_ml_s = 3.0;
  double concentration_mgI_ml = session::fluoro_control::kDefaultContrast_mgI_ml;
};

class CArmPanelModel {
 public:
  // Panel ranges (the C-arm's own are flow::check_pose's).
  static constexpr double kMinVolume_ml = 1.0;
  static constexpr double kMaxVolume_ml = 20.0;
  static constexpr double kMinRate_ml_s = 0.5;
  static constexpr double kMaxRate_ml_s = 10.0;
  static constexpr double kMinConcentration_mgI_ml = 140.0;  // iohexol 140 .. 350
  static constexpr double kMaxConcentration_mgI_ml = 350.0;
  static constexpr double kPulseRates[3] = {7.5, 15.0, 30.0};

  // The projections offered: flow::standard_projections(), then the case's working views.
  explicit CArmPanelModel(const std::vector<flow::NamedProjection>& case_views = {});

  // The unit's C-arm and pulse rate now (the session's snapshot): the fields show them.
  void sync(const flow::CArmPose& pose, double pulse_rate_hz);
  [[nodiscard]] const flow::CArmPose& pose() const { return pose_; }
  [[nodiscard]] double pulse_rate_hz() const { return rate_hz_; }
  [[nodiscard]] const std::vector<flow::NamedProjection>& projections() const { return projections_; }
  [[nodiscard]] const InjectionSettings& injection() const { return injection_; }
  // Why the last edit gave no control (empty when it gave one or changed nothing).
  [[nodiscard]] const std::string& error() const { return error_; }

  // Each edit: the control to post, or nullopt when nothing changes or the value is refused
  // (then error() names the field and its range).
  [[nodiscard]] std::optional<session::Control> set_angles(double lao_deg, double cranial_deg);
  [[nodiscard]] std::optional<session::Control> set_geometry(double sid_mm, double table_height_mm, double fov_mm,
                                                             double collimation);
  [[nodiscard]] std::optional<session::Control> set_pulse_rate(double per_s);
  [[nodiscard]] std::optional<session::Control> pick_projection(std::size_t index);
  // The injection settings (for the button and the I key): false with error() when out of range.
  bool set_injection(const InjectionSettings& s);
  [[nodiscard]] session::Control inject() const;
  [[nodiscard]] static session::Control capture_roadmap() { return session::fluoro_control::roadmap(true); }
  [[nodiscard]] static session::Control clear_roadmap() { return session::fluoro_control::roadmap(false); }

 private:
  std::optional<session::Control> move(const flow::CArmPose& next, bool angles);

  std::vector<flow::NamedProjection> projections_;
  flow::CArmPose pose_;
  double rate_hz_ = 15.0;
  InjectionSettings injection_;
  std::string error_;
};

}  // namespace cathbox::app
