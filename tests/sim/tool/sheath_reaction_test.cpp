// The reaction of a tool on the lumens around it (SheathFriction::reaction_mN), against the
// free-body balance of the inner tool: pushed in along a_entry with the hand's force F_hand and
// held at its distal end by a load F_distal along b_distal (its compression there), the lumen
// pushes on it with the sum of everything else, so what it pushes on the lumen with is
//   sum_j R_j = F_hand a_entry - F_distal b_distal
// (Newton's third law on a quasi-static rod; for a frictionless bend of theta this is the
// pulley's 2 F sin(theta / 2) along the bisector, the capstan's friction adding F_hand - F_distal
// = F_distal (e^(mu theta) - 1) along the path).
#include <cmath>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "sheath_path.hpp"
#include "tool/sheath_friction.hpp"

namespace cathbox::tool {
namespace {

// A path from the distal end back to the entry: straight along b_distal to the bend at the
// origin, then straight back along a_entry, the bend turning by theta over `arc` vertices.
std::vector<SheathVertex> bent_path(double theta, double mu, int arc) {
  const double r = 10.0;
  const double step = 1.0;
  // proximal straight from (0,0,-20) to (0,0,0) along +z, then an arc in the x-z plane, then straight
  std::vector<glm::dvec3> pts;
  for (int i = 0; i <= 20; ++i) pts.emplace_back(0.0, 0.0, -20.0 + i * step);
  for (int i = 1; i <= arc; ++i) {
    const double a = theta * i / arc;
    pts.emplace_back(r * (1.0 - std::cos(a)), 0.0, r * std::sin(a));
  }
  const glm::dvec3 out(std::sin(theta), 0.0, std::cos(theta));
  for (int i = 1; i <= 20; ++i) pts.push_back(pts.back() + out * step);
  return testing::sheath_path(pts, {.ei_Nmm2 = {}, .radius_mm = 0.125, .clearance_mm = 0.09, .mu = mu});  // a limp inner tool: the capstan alone
}

struct Balance {
  glm::dvec3 sum{0.0};
  glm::dvec3 expected{0.0};
};

Balance push(double theta, double mu, double distal_mN) {
  const std::vector<SheathVertex> path = bent_path(theta, mu, 16);
  SheathFriction f;
  f.set_bend_reaction(true);
  SheathFriction::Result r;
  for (int i = 0; i < 50; ++i) r = f.update(0.1, 0.0, distal_mN, path, 500.0);  // slipping forwards
  Balance b;
  for (const glm::dvec3& v : f.reaction_mN()) b.sum += v;
  const glm::dvec3 a_entry(0.0, 0.0, 1.0);
  const glm::dvec3 b_distal(std::sin(theta), 0.0, std::cos(theta));
  b.expected = (distal_mN + r.force_mN) * a_entry - distal_mN * b_distal;
  EXPECT_FALSE(r.sticking);
  return b;
}

// A coil compressed by 80 mN at its distal end (its push into a sac) through a frictionless 60
// degree curve (a microcatheter's steam-shaped tip): the lumen is pushed with 2 F sin(30 deg) =
// 80 mN along the bisector, outwards, half of it back along the tip's direction.
TEST(SheathReaction, AFrictionlessBendIsPushedLikeAPulley) {
  const double theta = M_PI / 3.0;
  const Balance b = push(theta, 0.0, 80.0);
  EXPECT_NEAR(glm::length(b.sum), 2.0 * 80.0 * std::sin(theta / 2.0), 0.5);
  EXPECT_NEAR(b.sum.x, b.expected.x, 0.5);
  EXPECT_NEAR(b.sum.z, b.expected.z, 0.5);
  EXPECT_NEAR(glm::dot(b.sum, glm::dvec3(std::sin(theta), 0.0, std::cos(theta))), -40.0, 0.5);
}

// With the liner's friction (mu 0.1, a coil in a microcatheter) through a half turn and a full
// 120 degrees: the capstan adds F_distal (e^(mu theta) - 1) along the path and the reactions still
// sum to the free body's balance (without the bends' push the holder felt the friction alone and
// was dragged forwards by it, nothing pushing it back).
TEST(SheathReaction, TheReactionsSumToTheInnerToolsFreeBodyBalance) {
  for (const double deg : {120.0, 180.0}) {
    const double theta = deg * M_PI / 180.0;
    const Balance b = push(theta, 0.1, 80.0);
    EXPECT_NEAR(b.sum.x, b.expected.x, 1.0) << deg;
    EXPECT_NEAR(b.sum.y, 0.0, 1e-9) << deg;
    EXPECT_NEAR(b.sum.z, b.expected.z, 1.0) << deg;
  }
}

}  // namespace
}  // namespace cathbox::tool
