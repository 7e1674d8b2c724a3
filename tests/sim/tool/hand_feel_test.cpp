// What the hand feels of a tool that touches nothing: the haemostatic valve's friction plus the
// viscous drag of blood, from physics; none of the solver's numerical damping.
#include <gtest/gtest.h>

#include <cmath>

#include "analytic_walls.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {
namespace {

// A 0.36 mm wire, straight, far from the wall of a 2 mm lumen along +z.
ToolSpec straight_wire() {
  ToolSpec w;
  w.name = "wire";
  w.sections = {ToolSection{600.0, 0.36, 40.0, 31.0, 0.0}, ToolSection{20.0, 0.36, 0.3, 0.23, 0.0}};
  return w;
}

struct Drive {
  Simulator& sim;
  // Moves the insertion to `target` at `speed` mm/s in 1 ms steps.
  void to(double target, double speed_mm_s) {
    const double per_step = speed_mm_s * 1e-3;
    while (std::abs(sim.insertion_mm(0) - target) > 1e-9) {
      const double d = std::clamp(target - sim.insertion_mm(0), -per_step, per_step);
      sim.set_insertion(0, sim.insertion_mm(0) + d);
      sim.step();
    }
  }
};

TEST(HandFeel, BloodDragFromItsViscosityIsTinyAgainstTheOldDefault) {
  // 2 pi mu / ln(R/a) for a 0.36 mm wire in a 2 mm lumen with blood at 3.5 mPa.s.
  const double c = blood_drag_mN_s_per_mm2(0.18, 3.5);
  EXPECT_NEAR(c, 2.0 * M_PI * 3.5e-6 / std::log(2.0 / 0.18), 1e-12);
  EXPECT_NEAR(c, 9.13e-6, 0.01e-6);
  // At 180 mm inserted and 20 mm/s: 0.03 mN (the old default drag gave 36 mN).
  EXPECT_LT(c * 180.0 * 20.0, 0.04);
  // Thicker tools and thicker blood drag more; a tool as wide as the lumen is capped, finite.
  EXPECT_GT(blood_drag_mN_s_per_mm2(0.8, 3.5), c);
  EXPECT_GT(blood_drag_mN_s_per_mm2(0.18, 5.0), c);
  EXPECT_TRUE(std::isfinite(blood_drag_mN_s_per_mm2(2.0, 3.5)));
}

TEST(HandFeel, AToolSlidingFreelyIsFeltAsTheValveFrictionPlusBloodDragOnly) {
  const TubeNetworkWall wall = testing::straight_tube(2.0, -10.0, 700.0);
  const std::vector<ToolSpec> tools = {straight_wire()};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
  Drive drive{sim};
  const double blood = blood_drag_mN_s_per_mm2(0.18, 3.5);
  drive.to(100.0, 20.0);
  const double at100 = sim.hand_force_mN(0);
  drive.to(180.0, 20.0);
  const double at180 = sim.hand_force_mN(0);
  // The valve (20 mN by default) plus 0.03 mN of blood; before, 36 mN rising 0.2 mN per mm.
  EXPECT_NEAR(at180, kDefaultValveFriction_mN + blood * 180.0 * 20.0, 0.05);
  EXPECT_LT(std::abs(at180 - at100) / 80.0, 0.002) << at100 << " -> " << at180;
  EXPECT_FALSE(sim.valve(0).sticking);
  // Pulled back, the same friction the other way.
  drive.to(160.0, 20.0);
  EXPECT_NEAR(sim.hand_force_mN(0), -kDefaultValveFriction_mN - blood * 160.0 * 20.0, 0.05);
  // Held still, the valve sticks: a push smaller than its limit is held by its stiffness.
  const double before = sim.hand_force_mN(0);
  sim.set_insertion(0, sim.insertion_mm(0) + 0.0005);
  sim.step();
  EXPECT_TRUE(sim.valve(0).sticking);
  EXPECT_GT(sim.hand_force_mN(0), before + 5.0);
  EXPECT_LT(sim.hand_force_mN(0), kDefaultValveFriction_mN);
  EXPECT_GT(sim.force_law(0).stiffness_mN_per_mm, 1e3);  // the box renders the stick
}

TEST(HandFeel, ACaseSetsTheValveAndAnExplicitDragIsFeltAsItsPhysicsBelowTheSolverFloor) {
  const TubeNetworkWall wall = testing::straight_tube(2.0, -10.0, 700.0);
  ToolSpec w = straight_wire();
  w.valve_friction_mN = 0.0;
  w.drag_mN_s_per_mm2 = 1e-4;  // below the solver's numerical floor (1e-2)
  const std::vector<ToolSpec> tools = {w};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
  Drive{sim}.to(180.0, 20.0);
  EXPECT_NEAR(sim.hand_force_mN(0), 1e-4 * 180.0 * 20.0, 0.05);  // 0.36 mN, not the floor's 36
  EXPECT_NEAR(sim.force_law(0).damping_mN_s_per_mm, 1e-4 * 180.0, 0.02);

  // Above the floor the drag is all physical: 0.05 x 150 mm x 5 mm/s = 37.5 mN.
  ToolSpec thick = straight_wire();
  thick.valve_friction_mN = 0.0;
  thick.drag_mN_s_per_mm2 = 0.05;
  const std::vector<ToolSpec> tools2 = {thick};
  Simulator sim2(wall, tools2, Entry{{0, 0, 0}, {0, 0, 1}});
  Drive{sim2}.to(150.0, 5.0);
  EXPECT_NEAR(sim2.hand_force_mN(0), 0.05 * 150.0 * 5.0, 0.05 * 37.5);
}

TEST(HandFeel, TwistingAFreeToolIsFeltAsTheValveTorqueOnly) {
  const TubeNetworkWall wall = testing::straight_tube(2.0, -10.0, 700.0);
  const std::vector<ToolSpec> tools = {straight_wire()};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
  Drive{sim}.to(150.0, 50.0);
  for (int i = 0; i < 500; ++i) {  // half a second at one turn per second
    sim.set_rotation(0, sim.rotation_rad(0) + 2.0 * M_PI * 1e-3);
    sim.step();
  }
  // The valve's friction at the wire's surface: 20 mN x 0.18 mm = 3.6 mN.mm; the wire's own
  // twist drag in blood is ~1e-4 mN.mm.
  EXPECT_NEAR(sim.hand_torque_mNmm(0), kDefaultValveFriction_mN * 0.18, 0.05);
  EXPECT_FALSE(sim.valve(0).twist_sticking);
}

}  // namespace
}  // namespace cathbox::tool
