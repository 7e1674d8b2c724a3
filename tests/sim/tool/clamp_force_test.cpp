// The force at the hand of a converged step (issue 29, "the feel"): the clamp force at the
// linearised equilibrium the convergence test read, also where the line search took the Newton
// step only in part. Reference: the same rod with RodSettings::linearised_clamp, which reads the
// clamp at that equilibrium on every step (g_p + K_pf d, the step d taken whole). A lone rod's hand
// force does not act back on its path, so the two rods move alike, node for node.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "analytic_walls.hpp"
#include "rod_test_support.hpp"
#include "tool/rod.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {
namespace {

TEST(ClampForce, AConvergedStepTakenInPartGivesTheHandItsLinearisedEquilibriumsForce) {
  // A stiff catheter (EI 200 N mm^2, 1.6 mm) pushed and pulled through a 90 degree bend of
  // radius 8 mm in a 1.4 mm lumen, with friction, at speeds that change and reverse.
  TubeNetworkWall wall;
  wall.add_polyline(testing::bend_points(8.0, M_PI / 2.0, 20.0, 80.0), 1.4, 0);
  wall.build();
  const ToolSpec spec = testing::uniform_tool(200.0, 1.6, 200.0, 150.0, 1.0, 0.2);
  RodSettings whole = RodSettings{};
  whole.linearised_clamp = true;
  Rod rod(spec, RodSettings{});
  Rod reference(spec, whole);
  for (Rod* r : {&rod, &reference}) r->set_entry({0, 0, -20}, {0, 0, 1});
  struct Move {
    double to_mm, per_step_mm;
  };
  const std::vector<Move> moves{{60, 0.02}, {40, 0.01}, {90, 0.005}, {85, 0.02}, {110, 0.01}, {100, 0.002}, {120, 0.02}};
  int converged = 0, taken_in_part = 0;
  double largest_apart_mN = 0.0, largest_read_off_mN = 0.0;
  for (const Move& m : moves) {
    double ins = rod.insertion_mm();
    while (std::abs(m.to_mm - ins) > 1e-12) {
      ins += std::clamp(m.to_mm - ins, -m.per_step_mm, m.per_step_mm);
      for (Rod* r : {&rod, &reference}) {
        r->set_boundary(ins, 0.0);
        r->step(1e-3, wall);
      }
      ASSERT_TRUE(rod.tip().position_mm == reference.tip().position_mm) << "the two rods left one path at " << ins << " mm";
      if (!rod.converged()) continue;
      ++converged;
      // A step taken whole gives the moves' clamp (both reads one); one taken in part, the
      // equilibrium's, which the reference reads on every step.
      const bool in_part = rod.hand_force_mN() != rod.clamp_read_mN();
      taken_in_part += in_part ? 1 : 0;
      if (in_part) {
        const double apart = std::abs(rod.hand_force_mN() - reference.hand_force_mN());
        largest_apart_mN = std::max(largest_apart_mN, apart);
        largest_read_off_mN = std::max(largest_read_off_mN, std::abs(rod.clamp_read_mN() - reference.hand_force_mN()));
        EXPECT_LE(apart, 1e-6 * std::max(1.0, std::abs(reference.hand_force_mN()))) << "at " << ins << " mm";
      }
    }
  }
  std::printf("%d converged steps, %d taken in part; on those the moves' clamp read up to %.1f mN off the whole step's, "
              "the hand %.3g mN\n",
              converged, taken_in_part, largest_read_off_mN, largest_apart_mN);
  EXPECT_GT(converged, 5000);
  EXPECT_GT(taken_in_part, 0) << "no converged step was taken in part: the run does not check the read";
}

}  // namespace
}  // namespace cathbox::tool
