#pragma once
// A robust filter for the radii of a centreline measured from images (VMTK's maximum inscribed
// sphere radius, a segmentation's distance map, a traced SWC): single points or short runs that
// disagree with their neighbourhood (outliers, sudden jumps that come straight back) are replaced
// by the neighbourhood's median; everything else is left exactly as it is, so real radius changes
// (a stenosis, a bulge, a step at a branch) survive as long as they span more points than the run.
//
// For each point of a segment, the window is the point and kRadiusWindow points on each side
// (shifted inward at the ends so it always holds 2 kRadiusWindow + 1 points when the segment
// has them). With m the window's median and s = 1.4826 * median(|r_j - m|) (the MAD, scaled to a
// standard deviation for normal noise), the point is an outlier when
//   |r - m| > max(kRadiusSigmas * s, kRadiusMinRelative * m)
// or r <= 0 or not finite; it then takes the value m (its neighbours' median of positive radii).
// With a window of 5 points, a run of up to 2 points is an outlier run; 3 or more are a feature.
#include <cstddef>
#include <string>

#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

constexpr int kRadiusWindow = 2;            // points on each side of the window
constexpr double kRadiusSigmas = 3.0;       // how many robust standard deviations make an outlier
constexpr double kRadiusMinRelative = 0.1;  // ... but never less than this fraction of the median

struct RadiusFilterReport {
  std::size_t points = 0;          // points looked at
  std::size_t changed = 0;         // points whose radius was replaced
  std::size_t segments_changed = 0;
  double max_relative_change = 0.0;  // largest |new - old| / new
  std::size_t unusable_segments = 0;  // segments without a single positive radius (left as they are)

  // "changed 3 of 812 radii (max 41 %)" or "changed no radius".
  [[nodiscard]] std::string summary() const;
};

// Filters every segment's radii in place.
RadiusFilterReport filter_radii(VesselModel& model);

}  // namespace cathbox::vessel
