#pragma once
// A swept tube whose centreline bends tighter than its own radius folds its inner wall over
// itself: the rings on the inside of the bend pass the bend's centre. The case generator keeps
// its bends at kMinBendRadii lumen radii or more (rounded_corner in src/neuro_shapes.cpp); a
// centreline from elsewhere (a file, a surface's skeleton) gets the same bound here.
//
// A bend is measured at each inner point of a segment: the circle through it and its two
// neighbours, over the point's radius (a point where the centreline folds straight back counts
// as 0). The mesher sweeps its tube along the centreline after smoothing it (Taubin, 3 passes by
// default, centerline_smoother.hpp), and smoothing unevenly spaced points can tighten a bend: the
// old ica_coil's loop measured 1.145 radii as written and 0.826 as swept, and its wall crossed
// itself (42 triangle pairs). So the guard measures the swept centreline (swept_centerline: the
// default smoothing of the segment alone, its ends fixed). Circular bends swept by the mesher
// cross themselves at 0.96 radii and below and never from 1.0 up (measured on the swept line; M =
// 4, 8 and 12, points 0.25-1 radii apart: tests/sim/vessel/bend_bound_test.cpp), as the geometry
// says; the bound keeps a margin of 14 % above that for bends that are not circles.
// round_tight_bends relaxes the points around a bend tighter than the bound (on the swept line)
// towards their neighbours' midpoint (a Laplacian step, half a step at a time, ends fixed) until no
// swept bend of the segment is tighter: the corner becomes an arc. Radii are left as they are.
#include <cstddef>
#include <string>
#include <vector>

#include "vessel/segment.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

constexpr double kMinBendRadii = 1.1;  // the generator's bound (case_library_test.cpp checks it)

// The tightest bend of a segment's centreline over the radius there (infinity when straight).
[[nodiscard]] double tightest_bend_over_radius(const Segment& segment);
// The centreline the mesher sweeps for this segment with the default MeshOptions, and its tightest
// bend: the bound applies to this one.
[[nodiscard]] std::vector<CenterlinePoint> swept_centerline(const Segment& segment);
[[nodiscard]] double tightest_swept_bend_over_radius(const Segment& segment);

struct BendGuardReport {
  double bound = kMinBendRadii;      // in lumen radii
  std::size_t bends = 0;             // segments that had a bend tighter than the bound
  std::size_t points_moved = 0;
  std::size_t left_tight = 0;        // segments still tighter after the pass limit
  double tightest_before = 0.0;      // the tightest swept bend found, in radii
  double max_move_mm = 0.0;          // the largest distance a point was moved

  // "2 bends tighter than 1.1 lumen radii rounded (tightest 0.354 radii; 7 points moved up to 0.61 mm)"
  // or empty when nothing was done.
  [[nodiscard]] std::string summary() const;
};

// Rounds every segment's bends tighter than min_bend_radii radii in place.
BendGuardReport round_tight_bends(VesselModel& model, double min_bend_radii = kMinBendRadii);

}  // namespace cathbox::vessel
