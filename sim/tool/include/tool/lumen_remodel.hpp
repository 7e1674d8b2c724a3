#pragma once
// What an inflated balloon does to the vessel: the lumen radii of the central-axis model along
// the balloon's working length, and the stenosis measured on them.
//
// Vessel-wall model (deliberately simple): while the balloon is inflated, every centre-line
// point under its working length takes at least the balloon's (unconstrained) radius; the
// largest radius a point was stretched to is remembered, and once the balloon is no longer
// pressing it the lumen recoils elastically by a fraction of the gain:
//   r = r0 + (1 - recoil) (r_peak - r0),        recoil = 0.25 by default.
// Acute elastic recoil after balloon angioplasty is reported by quantitative angiography as a
// loss of roughly a fifth to a half of the diameter gained (coronary series, e.g. Rensing et
// al., Am J Cardiol 1991; intracranial series give residual stenoses of 20-40 %); 0.25 is a
// value in that range, a parameter here, not a fit. No dissection, plaque shift or time
// course: the lumen is what the balloon made it, less the recoil, at once.
//
// Stenosis, as quantitative angiography grades it: stenosis % = 100 (1 - minimal lumen diameter
// / reference diameter), the reference interpolated across the lesion from the healthy vessel
// on both sides of it (QCA's interpolated reference diameter: Reiber et al., Circulation
// 1985;71:280-8; NASCET and WASID likewise grade against normal artery of the same vessel,
// N Engl J Med 1991;325:445-53, Samuels et al., AJNR 2000;21:643-6). Here: the line through
// the widest point 5-10 mm proximal and the widest 5-10 mm distal along the segment, read at
// the point (a tapering artery is its own reference). A point without vessel 5 mm past it on
// both sides is not graded: the neck of a blind aneurysm sac against its dome, or a segment's
// end against the wider vessel it tapers from, is no lesion. The lesion is the point of the
// model with the largest narrowing, with the contiguous points around it that are narrower
// than 90 % of their reference.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

struct Lesion {
  std::size_t segment = 0;        // index into VesselModel::segments
  std::size_t first = 0, last = 0;  // points of the lesion (inclusive)
  std::size_t worst = 0;          // its narrowest point at the start
  double reference_diameter_mm = 0.0;  // at the narrowest point (stays the reference)
  [[nodiscard]] bool found() const { return reference_diameter_mm > 0.0; }
};

// Interpolated reference radius at point i of segment s (see above); 0 where the segment does
// not reach 5 mm past the point on both sides.
[[nodiscard]] double reference_radius(const vessel::Segment& s, std::size_t i);
// The reference a balloon is sized against where it sits: reference_radius, else the widest
// radius of the one window the segment reaches, else the point's own radius.
[[nodiscard]] double sizing_reference_radius(const vessel::Segment& s, std::size_t i);
// The narrowest point of the model against its reference, and the lesion around it (not
// found when nothing is narrowed by 10 % or more).
[[nodiscard]] Lesion find_lesion(const vessel::VesselModel& model);
// Diameter stenosis in % at the lesion: the smallest diameter over its points against its
// reference diameter (0 when the lumen is at least the reference).
[[nodiscard]] double stenosis_percent(const vessel::VesselModel& model, const Lesion& lesion);

struct LumenRemodelParams {
  double recoil = 0.25;          // fraction of the gained radius lost after deflation, [0, 1]
  double min_change_mm = 0.05;   // smaller radius changes do not ask for a new wall
  double oversize_ratio = 1.1;   // balloon diameter above this x reference: rupture risk
};

// The balloon as the remodel sees it: its axis from the proximal to the distal end of the
// working length (Simulator::balloon_axis), its diameter and whether it is inflated.
struct BalloonPose {
  std::span<const glm::dvec3> axis_mm;
  double diameter_mm = 0.0;
  bool inflated = false;
};

class LumenRemodel {
 public:
  // `source` is the vessel model the wall was meshed from (the HCLM as read).
  explicit LumenRemodel(vessel::VesselModel source, const LumenRemodelParams& params = {});

  // Applies one balloon for this tick. Returns true when some radius moved more than
  // min_change_mm away from the model last taken by take_model() (a new wall is due).
  bool apply(const BalloonPose& balloon);
  // The present lumen; marks it as the one the next wall is built from.
  [[nodiscard]] const vessel::VesselModel& take_model();
  [[nodiscard]] const vessel::VesselModel& model() const { return model_; }

  [[nodiscard]] const Lesion& lesion() const { return lesion_; }
  [[nodiscard]] double stenosis_before_percent() const { return before_percent_; }
  [[nodiscard]] double stenosis_percent() const { return tool::stenosis_percent(model_, lesion_); }
  // Inflations whose balloon exceeded oversize_ratio x the reference diameter under it (each
  // inflation counts once), and the largest such ratio seen.
  [[nodiscard]] int rupture_risk_events() const { return rupture_events_; }
  [[nodiscard]] double max_oversize_ratio() const { return max_ratio_; }

 private:
  // Points of the segment under the balloon: segment index and inclusive point range.
  struct Span {
    std::size_t segment = 0, first = 1, last = 0;
  };
  [[nodiscard]] Span covered(std::span<const glm::dvec3> axis) const;
  void set_radius(std::size_t s, std::size_t i, double r);

  vessel::VesselModel model_;
  // Per segment, per point: original radius, largest radius stretched to, radius of the last
  // model taken; arc length, reference radius of the original (all allocated here: apply()
  // runs on the haptic thread and allocates nothing).
  std::vector<std::vector<double>> r0_, peak_, taken_, arc_, ref0_;
  LumenRemodelParams params_;
  Lesion lesion_;
  double before_percent_ = 0.0;
  bool pressing_ = false;  // the previous tick's balloon was inflated over some points
  Span last_span_;
  bool over_ = false;      // this inflation is already counted as a rupture risk
  int rupture_events_ = 0;
  double max_ratio_ = 0.0;
};

}  // namespace cathbox::tool
