// The detachment zone as it parts (Rod::soften_joint, Simulator::detach): a softened joint is a
// hinge in the beam whose compliance grows as its stiffness share falls, against Euler-Bernoulli
// with a rotational spring; restored, the beam is as built.
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "rod_test_support.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {
namespace {

using testing::NoWall;
using testing::static_settings;
using testing::uniform_tool;

// A cantilever L past its clamp, loaded across its tip by P, the joint a from the tip. The vertex
// there bends over its Voronoi length h with EI s instead of EI: a rotational spring of EI s / h
// in place of EI / h, so the moment P a at it turns the distal part by P a h (1/s - 1) / EI more,
// and the tip moves by that angle times a: delta = P a^2 h (1/s - 1) / EI over the beam's
// P L^3 / 3 EI (Timoshenko & Gere, Mechanics of Materials: a beam with an elastic hinge).
double tip_deflection_mm(double share, double joint_from_tip_mm) {
  Rod rod(uniform_tool(60.0, 0.5, 10.0, 8.0, 1.0, 0.0), static_settings());
  NoWall wall;
  rod.set_entry({0, 0, 0}, {0, 0, 1});
  rod.set_boundary(40.0, 0.0);
  EXPECT_TRUE(rod.soften_joint(joint_from_tip_mm, share));
  rod.set_node_load(rod.node_total() - 1, {0.2, 0, 0});
  for (int i = 0; i < 10; ++i) rod.step(1e-3, wall);
  return rod.tip().position_mm.x;
}

TEST(DetachmentZone, ASoftenedJointIsAnElasticHingeInTheBeam) {
  const double P = 0.2, ei = 10.0 * 1000.0, h = 1.0, a = 10.0;  // mN, mN mm^2, mm, mm
  const double whole = tip_deflection_mm(1.0, a);
  EXPECT_NEAR(whole / (P * 40.0 * 40.0 * 40.0 / (3.0 * ei)), 1.0, 0.03);
  for (const double s : {0.5, 0.1, 0.02}) {
    const double extra = tip_deflection_mm(s, a) - whole;
    const double expected = P * a * a * h * (1.0 / s - 1.0) / ei;
    EXPECT_NEAR(extra / expected, 1.0, 0.03) << "share " << s;
    std::printf("joint at share %.2f: the tip %.4f mm further, the elastic hinge's %.4f mm\n", s, extra, expected);
  }
  // Not a vertex (between nodes) or too near an end: refused.
  Rod rod(uniform_tool(60.0, 0.5, 10.0, 8.0, 1.0, 0.0), static_settings());
  rod.set_entry({0, 0, 0}, {0, 0, 1});
  rod.set_boundary(40.0, 0.0);
  EXPECT_FALSE(rod.soften_joint(10.5, 0.5));
  EXPECT_FALSE(rod.soften_joint(0.0, 0.5));
}

// Softened, then restored to 1: the beam is as built, bit for bit.
TEST(DetachmentZone, ARestoredJointIsTheBuiltOne) {
  Rod built(uniform_tool(60.0, 0.5, 10.0, 8.0, 1.0, 0.0), static_settings());
  Rod restored(uniform_tool(60.0, 0.5, 10.0, 8.0, 1.0, 0.0), static_settings());
  NoWall wall;
  for (Rod* r : {&built, &restored}) {
    r->set_entry({0, 0, 0}, {0, 0, 1});
    r->set_boundary(40.0, 0.0);
    r->set_node_load(r->node_total() - 1, {0.2, 0, 0});
  }
  ASSERT_TRUE(restored.soften_joint(10.0, 0.01));
  ASSERT_TRUE(restored.soften_joint(10.0, 0.3));
  ASSERT_TRUE(restored.soften_joint(10.0, 1.0));
  for (int i = 0; i < 10; ++i) {
    built.step(1e-3, wall);
    restored.step(1e-3, wall);
  }
  EXPECT_EQ(built.tip().position_mm.x, restored.tip().position_mm.x);
}

}  // namespace
}  // namespace cathbox::tool
