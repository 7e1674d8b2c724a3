// The lumen's bending push (SheathFriction): the shear the lumen holds where the inner tool's
// bending moment M = EI k changes (beam theory, V = dM/ds). Along a circular arc of curvature k a
// tool whose stiffness steps from EI1 to EI2 (a wire's core ending in its soft tip) has its moment
// step by |EI1 - EI2| k there: the lumen holds that change as a shear, |EI1 - EI2| k / l summed
// over the edges round the step (l the length over which the radial clearance c lets the tool
// take it up, 2 sqrt(2 c / k), never shorter than the edge). Pushes from a change of curvature
// alone (EI dk / l) leave this out: where the curvature is uniform they read nothing at the step.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "sheath_path.hpp"
#include "tool/sheath_friction.hpp"

namespace cathbox::tool {
namespace {

constexpr double kRadius_mm = 10.0;     // the arc's
constexpr double kClearance_mm = 0.09;  // a 0.36 mm wire in a 0.53 mm lumen
constexpr int kArc = 16;                // chords over the arc
constexpr double kTheta = M_PI / 2.0;

struct Arc {
  std::vector<SheathVertex> path;  // distal first
  double curvature_per_mm = 0.0;   // the path's at each vertex inside the arc
  double chord_mm = 0.0;
};

// Straight, a quarter circle, straight; the straight parts' edges as long as the arc's chords, so
// its two ends mirror each other. ei(i) gives the inner tool's stiffness at point i (proximal first).
template <class Ei>
Arc quarter_arc(double mu, Ei ei) {
  const double da = kTheta / kArc;
  Arc a;
  a.chord_mm = 2.0 * kRadius_mm * std::sin(da / 2.0);
  a.curvature_per_mm = da / a.chord_mm;  // the turning over the mean of the two edges
  std::vector<glm::dvec3> pts;
  const glm::dvec3 in(0.0, 0.0, 1.0);
  for (int i = -10; i <= 0; ++i) pts.push_back(in * (i * a.chord_mm));
  for (int i = 1; i <= kArc; ++i) pts.emplace_back(kRadius_mm * (1.0 - std::cos(da * i)), 0.0, kRadius_mm * std::sin(da * i));
  const glm::dvec3 out(std::sin(kTheta), 0.0, std::cos(kTheta));
  for (int i = 1; i <= 10; ++i) pts.push_back(pts.back() + out * a.chord_mm);
  const std::size_t arc_middle = 10 + kArc / 2;
  a.path = testing::sheath_path(pts, {.ei_Nmm2 = [&](std::size_t i) { return ei(i, arc_middle); },
                                      .radius_mm = 0.18, .clearance_mm = kClearance_mm, .mu = mu});
  return a;
}

// The slip limit forwards with no axial load at the distal end: mu times the bending pushes (and
// the capstan on the friction they make, second order in mu).
double slip_limit(const std::vector<SheathVertex>& path) {
  SheathFriction f;
  SheathFriction::Result r;
  for (int i = 0; i < 20; ++i) r = f.update(0.1, 0.0, 0.0, path, 500.0);
  EXPECT_FALSE(r.sticking);
  return r.force_limit_fwd_mN;
}

TEST(SheathBending, AStiffnessStepOnAnArcPushesTheLumenWithTheMomentsChange) {
  constexpr double kMu = 1e-3;
  constexpr double kCore = 40.0, kTip = 3.0;  // N mm^2: the bundled microwire's core and soft tip
  // At the step's vertex the stiffness over its span, its two halves in series (as the simulator
  // gives it: Simulator::cover_sheath_path).
  const double series = 2.0 / (1.0 / kCore + 1.0 / kTip);
  const Arc core = quarter_arc(kMu, [&](std::size_t, std::size_t) { return kCore; });
  const Arc tip = quarter_arc(kMu, [&](std::size_t, std::size_t) { return kTip; });
  const Arc step = quarter_arc(kMu, [&](std::size_t i, std::size_t middle) {
    return i < middle ? kCore : i == middle ? series : kTip;  // the core proximal, the tip distal
  });
  const double k = step.curvature_per_mm;
  const double l = std::max(step.chord_mm, 2.0 * std::sqrt(2.0 * kClearance_mm / k));
  // The arc's two ends push alike in all three (mirrored, each with its own stiffness), so the
  // stepped arc reads the mean of the uniform ones plus the step's shear.
  const double shear_mN = 1e3 * std::abs(kCore - kTip) * k / l;
  const double extra_mN = slip_limit(step.path) - 0.5 * (slip_limit(core.path) + slip_limit(tip.path));
  std::printf("arc of radius %.0f mm, EI %.0f -> %.0f N mm^2 at its middle: the step's shear %.1f mN (analytic "
              "%.1f mN), times mu %.0e in the slip limit\n",
              kRadius_mm, kCore, kTip, extra_mN / kMu, shear_mN, kMu);
  EXPECT_NEAR(extra_mN / kMu, shear_mN, 0.01 * shear_mN);
}

// A uniform tool on the same arc: the moment changes only where the curvature does (the arc's
// ends), so its pushes are EI |dk| / l there, proportional to EI.
TEST(SheathBending, AUniformToolsPushScalesWithItsStiffness) {
  constexpr double kMu = 1e-3;
  const Arc soft = quarter_arc(kMu, [](std::size_t, std::size_t) { return 3.0; });
  const Arc stiff = quarter_arc(kMu, [](std::size_t, std::size_t) { return 30.0; });
  const double a = slip_limit(soft.path), b = slip_limit(stiff.path);
  ASSERT_GT(a, 0.0);
  EXPECT_NEAR(b / a, 10.0, 0.01);
}

}  // namespace
}  // namespace cathbox::tool
