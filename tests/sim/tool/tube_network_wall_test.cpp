#include "tool/tube_network_wall.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

namespace cathbox::tool {
namespace {

TEST(TubeNetworkWall, StraightTubeDistanceAndNormal) {
  TubeNetworkWall wall({Tube{{0, 0, 0}, {0, 0, 20}, 1.0, 1.0, 3}});
  WallProbe probe;
  probe.center_mm = {0.6, 0, 10};
  probe.radius_mm = 0.2;
  WallHint hint;
  WallContact c;
  ASSERT_TRUE(wall.probe(probe, hint, c));
  EXPECT_NEAR(c.distance_mm, 0.4, 1e-12);
  EXPECT_NEAR(c.normal.x, 1.0, 1e-12);
  EXPECT_NEAR(c.point_mm.x, 1.0, 1e-12);
  EXPECT_EQ(c.segment, 3);
  probe.center_mm = {0.0, 0, 10};
  probe.range_mm = 0.5;
  EXPECT_FALSE(wall.probe(probe, hint, c));  // 0.8 mm of clearance > range
  EXPECT_NEAR(wall.signed_distance({1.5, 0, 10}), -0.5, 1e-12);
}

TEST(TubeNetworkWall, UnionTakesTheDeepestTube) {
  TubeNetworkWall wall({Tube{{0, 0, 0}, {0, 0, 10}, 1.0, 1.0, 0}, Tube{{0, 0, 10}, {10, 0, 10}, 1.0, 1.0, 1}});
  std::int32_t seg = -1;
  EXPECT_NEAR(wall.signed_distance({0, 0, 5}, &seg), 1.0, 1e-12);
  EXPECT_EQ(seg, 0);
  EXPECT_NEAR(wall.signed_distance({5, 0, 10}, &seg), 1.0, 1e-12);
  EXPECT_EQ(seg, 1);
}

// A parent lumen of radius 2 mm along +z ending at the origin, and a branch of radius 1.2 mm from
// there towards (12, 0, 30): the lumen read walked along the parent's axis from z = -5 and on
// along the branch's for 5 mm, in 1 um steps. Returns the largest |dr/ds| (per mm of path).
constexpr double kParentR = 2.0;
constexpr double kBranchR = 1.2;
const glm::dvec3 kBranchEnd{12.0, 0.0, 30.0};

double steepest_lumen_read(const std::function<double(const glm::dvec3&)>& read) {
  const glm::dvec3 along = glm::normalize(kBranchEnd);
  constexpr double kStep = 1e-3;
  double steepest = 0.0;
  double last = read({0, 0, -5});
  for (double s = -5.0 + kStep; s <= 5.0; s += kStep) {
    const glm::dvec3 p = s < 0.0 ? glm::dvec3(0, 0, s) : s * along;
    const double r = read(p);
    steepest = std::max(steepest, std::abs(r - last) / kStep);
    last = r;
  }
  return steepest;
}

// Two lumens whose weights are d^2 (LumenBlend on their axes, where h = D): with one depth fixed
// at c and the other falling at 1 mm/mm, dr/ds = 2 dR x c^2 / (x^2 + c^2)^2 is largest at
// x = c / sqrt(3): 9 / (8 sqrt 3) dR / c. Along the branch (c = 1.2 mm) that is 0.433 per mm; along
// the parent (c = 2 mm) 0.260. The deepest tube alone jumps 0.8 mm at once (800 per mm here).
const double kSteepestBlend = 9.0 / (8.0 * std::sqrt(3.0)) * (kParentR - kBranchR) / kBranchR;

TEST(TubeNetworkWall, LumenRadiusIsContinuousAcrossAJunction) {
  const TubeNetworkWall wall({Tube{{0, 0, -40}, {0, 0, 0}, kParentR, kParentR, 0},
                              Tube{{0, 0, 0}, kBranchEnd, kBranchR, kBranchR, 1}});
  EXPECT_NEAR(steepest_lumen_read([&](const glm::dvec3& p) { return wall.lumen_radius_mm(p); }), kSteepestBlend, 0.005);
  // Alone in a tube (every other more than its depth shallower) the read is that tube's radius.
  EXPECT_DOUBLE_EQ(wall.lumen_radius_mm({0.5, 0, -10}), kParentR);
  EXPECT_DOUBLE_EQ(wall.lumen_radius_mm(4.0 * glm::normalize(kBranchEnd)), kBranchR);
  EXPECT_LT(TubeNetworkWall().lumen_radius_mm({0, 0, 0}), 0.0);
}

// The blend holds at most 32 tubes in place and drops those that weigh nothing at the deepest so
// far: whatever the order and count (here up to 200, many that weigh and many that never do), its
// read is the weighted mean of every tube's, bit for bit, summed in the order they were added.
TEST(LumenBlend, ReadsEveryWeighingTubeHowManySoEver) {
  std::uint64_t x = 0x9e3779b97f4a7c15ull;
  const auto uniform = [&x] {
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    return static_cast<double>(x >> 11) / 9007199254740992.0;
  };
  for (const int count : {1, 5, 31, 32, 33, 64, 200}) {
    for (int round = 0; round < 20; ++round) {
      std::vector<std::pair<double, double>> tubes;
      for (int i = 0; i < count; ++i) {
        const double depth = -1.0 + 3.0 * uniform();  // some outside, some deep
        tubes.emplace_back(depth, 0.5 + 2.0 * uniform());
      }
      LumenBlend blend;
      double deepest = -std::numeric_limits<double>::infinity();
      for (const auto& [d, r] : tubes) {
        blend.add(d, r);
        deepest = std::max(deepest, d);
      }
      const double band = std::max(deepest, LumenBlend::kBand_mm);
      double w = 0.0;
      double wr = 0.0;
      for (const auto& [d, r] : tubes) {
        const double lift = d - deepest + band;
        if (lift > 0.0) w += lift * lift, wr += lift * lift * r;
      }
      EXPECT_EQ(blend.radius_mm(), wr / w) << count << " tubes, round " << round;
    }
  }
  EXPECT_LT(LumenBlend().radius_mm(), 0.0);
}

TEST(CentrelineRadius, IsContinuousAcrossAJunction) {
  vessel::VesselModel model;
  vessel::Segment parent;
  parent.id = 0;
  for (int i = 0; i <= 40; ++i) parent.points.push_back({{0, 0, -40.0 + i}, kParentR});
  vessel::Segment branch;
  branch.id = 1;
  for (int i = 0; i <= 30; ++i) branch.points.push_back({kBranchEnd * (i / 30.0), kBranchR});
  model.segments = {parent, branch};
  EXPECT_NEAR(steepest_lumen_read([&](const glm::dvec3& p) { return centreline_radius_mm(model, p); }), kSteepestBlend, 0.005);
  EXPECT_DOUBLE_EQ(centreline_radius_mm(model, {0.5, 0, -10}), kParentR);
  EXPECT_LT(centreline_radius_mm(vessel::VesselModel{}, {0, 0, 0}), 0.0);
}

}  // namespace
}  // namespace cathbox::tool
