#include "app/carm_panel_model.hpp"

#include <algorithm>
#include <cstdio>

namespace cathbox::app {
namespace fc = session::fluoro_control;

CArmPanelModel::CArmPanelModel(const std::vector<flow::NamedProjection>& case_views)
    : projections_(flow::standard_projections()) {
  for (const flow::NamedProjection& v : case_views) {
    flow::NamedProjection named = v;
    named.name = "case: " + v.name;
    projections_.push_back(std::move(named));
  }
}

void CArmPanelModel::sync(const flow::CArmPose& pose, double pulse_rate_hz) {
  pose_ = pose;
  rate_hz_ = pulse_rate_hz;
}

std::optional<session::Control> CArmPanelModel::move(const flow::CArmPose& next, bool angles) {
  error_.clear();
  if (next == pose_) return std::nullopt;
  if (std::string e = flow::check_pose(next); !e.empty()) {
    error_ = std::move(e);
    return std::nullopt;
  }
  pose_ = next;
  if (angles) return fc::carm_angles(next.lao_deg, next.cranial_deg);
  return fc::carm_geometry(next.sid_mm, next.table_height_mm, next.fov_mm, next.collimation);
}

std::optional<session::Control> CArmPanelModel::set_angles(double lao_deg, double cranial_deg) {
  flow::CArmPose next = pose_;
  next.lao_deg = lao_deg;
  next.cranial_deg = cranial_deg;
  return move(next, true);
}

std::optional<session::Control> CArmPanelModel::set_geometry(double sid_mm, double table_height_mm, double fov_mm,
                                                             double collimation) {
  flow::CArmPose next = pose_;
  next.sid_mm = sid_mm;
  next.table_height_mm = table_height_mm;
  next.fov_mm = fov_mm;
  next.collimation = collimation;
  return move(next, false);
}

std::optional<session::Control> CArmPanelModel::set_pulse_rate(double per_s) {
  error_.clear();
  if (per_s == rate_hz_) return std::nullopt;
  if (std::find(std::begin(kPulseRates), std::end(kPulseRates), per_s) == std::end(kPulseRates)) {
    char line[96];
    std::snprintf(line, sizeof line, "pulse rate: %g per s is not 7.5, 15 or 30", per_s);
    error_ = line;
    return std::nullopt;
  }
  rate_hz_ = per_s;
  return fc::pulse_rate(per_s);
}

std::optional<session::Control> CArmPanelModel::pick_projection(std::size_t index) {
  if (index >= projections_.size()) {
    error_ = "projection " + std::to_string(index) + ": there are " + std::to_string(projections_.size());
    return std::nullopt;
  }
  return set_angles(projections_[index].lao_deg, projections_[index].cranial_deg);
}

bool CArmPanelModel::set_injection(const InjectionSettings& s) {
  error_.clear();
  const auto outside = [&](const char* field, double v, double lo, double hi, const char* unit) {
    if (v >= lo && v <= hi) return false;  // also refuses NaN
    char line[128];
    std::snprintf(line, sizeof line, "injection %s: %g %s, must be in [%g, %g]", field, v, unit, lo, hi);
    error_ = line;
    return true;
  };
  if (outside("volume", s.volume_ml, kMinVolume_ml, kMaxVolume_ml, "mL") ||
      outside("rate", s.rate_ml_s, kMinRate_ml_s, kMaxRate_ml_s, "mL/s") ||
      outside("concentration", s.concentration_mgI_ml, kMinConcentration_mgI_ml, kMaxConcentration_mgI_ml, "mgI/mL")) {
    return false;
  }
  injection_ = s;
  return true;
}

session::Control CArmPanelModel::inject() const {
  return fc::inject(injection_.volume_ml, injection_.rate_ml_s, injection_.concentration_mgI_ml);
}

}  // namespace cathbox::app
