// Two shapes of the public stEVE_bench aortic-arch curves (lkarstensen/stEVE_bench, MIT;
// docs/vessel-import/real-files.md) that read more than 5 % off before, rebuilt here: a hairpin
// whose other limb lies within the probe's reach (the carotid siphon, segment 13 of the 25-curve
// set: +10.9 % was the probe's), and a thin artery widening 3.5-fold within two points just after a
// bend (a posterior cerebral artery joined to the basilar top: -5.3 % was the mesher's).
#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "radius_probe.hpp"
#include "vessel/hclm.hpp"
#include "vessel_test_support.hpp"

namespace cathbox::vessel {
namespace {

constexpr double kPi = 3.14159265358979323846;

// A 2 mm tube up 20 mm, round a semicircle of 2.5 mm (1.25 radii) and down again: the limbs'
// walls 1 mm apart. A cut across one limb within 1.8 radii of its axis reaches the other limb's
// near wall (3-3.6 mm out); that wall lies behind this limb's own, seen from the axis, and is
// left out (radius_probe.hpp): within 0.5 %. Counted, the limb cuts read up to +8.9 % and the
// worst cut along the segment +10.9 %.
TEST(RadiusFidelity, AHairpinsOtherLimbIsNotReadAsThisLumen) {
  constexpr double r = 2.0;
  constexpr double rho = 2.5;
  VesselModel model;
  Segment s;
  s.id = 1;
  for (double z = 0.0; z < 20.0; z += 0.5) s.points.push_back({{0.0, 0.0, z}, r});
  for (int k = 0; k <= 24; ++k) {
    const double a = kPi - kPi * k / 24.0;
    s.points.push_back({{rho + rho * std::cos(a), 0.0, 20.0 + rho * std::sin(a)}, r});
  }
  for (double z = 19.5; z >= 0.0; z -= 0.5) s.points.push_back({{2.0 * rho, 0.0, z}, r});
  model.segments.push_back(s);
  ASSERT_TRUE(validate_model(model).empty());
  const VesselSurface surface = build_vessel_surface(model);
  test::expect_valid_surface(surface, model);
  if (HasFatalFailure()) return;
  int hiding = 0;
  double worst = 0.0;
  for (double z = 4.0; z <= 16.0; z += 1.0) {
    const test::Cut cut = test::cut_surface(surface.mesh, {0.0, 0.0, z}, {0.0, 0.0, 1.0}, 1.8 * r);
    EXPECT_TRUE(cut.closed()) << z;
    hiding += cut.hidden > 0 ? 1 : 0;
    worst = std::max(worst, std::abs(cut.mean / r - 1.0));
  }
  const test::ProfileError along = test::worst_along_segments(model, surface);
  std::printf("hairpin: limb cuts with the other limb hidden %d of 13, worst %.2f %%; along the segment worst %+.2f %% over %d cuts\n",
              hiding, 100.0 * worst, 100.0 * along.worst, along.samples);
  EXPECT_EQ(hiding, 13) << "the other limb is no longer within the reach: the test shows nothing";
  EXPECT_LT(worst, 0.01);
  EXPECT_LT(std::abs(along.worst), 0.03);
}

// Points 1 mm apart, 0.55 -> 1.02 -> 1.95 mm within two points, the line turning 13 degrees at
// the ramp's foot and 20 back at each of the next two (the curve: 0.55, 1.02, 1.95 mm, turns of
// 10-34 degrees a point there). Rings are added along the ramp 0.1-0.2 mm apart; next to 1 mm
// steps the uniform B-spline through them overshoots, and the tube's foot came out -5.5 % (0.576
// mm for 0.609; the curve's -5.3 %: 0.576 for 0.608). With the spacing graded into the
// neighbours (ring_arcs.cpp) -2.0 %.
TEST(RadiusFidelity, ARadiusRampJustAfterABendFollowsTheInput) {
  VesselModel model;
  Segment s;
  s.id = 1;
  glm::dvec3 p{0.0};
  glm::dvec3 dir{0.0, 0.0, 1.0};
  const auto turn = [&](double degrees) {
    const double a = degrees * kPi / 180.0;
    dir = glm::normalize(glm::dvec3(dir.x * std::cos(a) + dir.z * std::sin(a), 0.0, -dir.x * std::sin(a) + dir.z * std::cos(a)));
  };
  for (int i = 0; i < 30; ++i) {
    const double radius = i < 12 ? 0.55 : i == 12 ? 1.02 : 1.95;
    s.points.push_back({p, radius});
    if (i == 11) turn(13.0);
    if (i == 12 || i == 13) turn(-20.0);
    p += dir;
  }
  model.segments.push_back(s);
  ASSERT_TRUE(validate_model(model).empty());
  const VesselSurface surface = build_vessel_surface(model);
  test::expect_valid_surface(surface, model);
  if (HasFatalFailure()) return;
  const test::ProfileError e = test::worst_along_segments(model, surface);
  std::printf("ramp after a bend: worst %+.2f %% at arc %.2f mm (%.3f for %.3f) over %d cuts\n", 100.0 * e.worst, e.worst_arc,
              e.worst_surface, e.worst_input, e.samples);
  EXPECT_GT(e.samples, 100);
  EXPECT_LT(std::abs(e.worst), 0.03);
}

}  // namespace
}  // namespace cathbox::vessel
