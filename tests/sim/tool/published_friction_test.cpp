// The friction of a coil's pusher inside a microcatheter, as the simulator's default lumen liner
// gives it, against published coefficients (issue 29, item 3; sim/tool/README.md, "Hand forces
// against published measurements").
//
// Sources (what was read, and where):
// - *Handbook of Surface Improvement and Modification* (Wypych, ChemTec 2018; the page read
//   showed its title and p. 167, not the author or year), Table 11.1 ("Friction coefficients
//   of common materials"): PTFE on steel, static 0.18, dynamic 0.16 (dry). A stainless pusher in a PTFE-lined lumen is this pair; a saline-flushed lumen is
//   lubricated, so the dry dynamic coefficient is the upper bound.
// - Schroeder J, *The mechanical properties of guidewires. Part III: Sliding friction*,
//   Cardiovasc Intervent Radiol 16(2):93-97, 1993 (abstract): "Teflon coating reduces the
//   sliding friction to one-half, and a hydrophilic plastic coat to about one-sixth compared
//   with steel." The lowest coefficient a wire in a catheter is given by its coating is then
//   about a sixth of the bare steel one: 0.16 / 6 = 0.027, the lower bound (derived from the
//   two sources, not itself a measurement).
// The simulator's coefficient is measured, not read from the spec: the pusher is pushed, then
// pulled, through the microcatheter turning by theta = 180 degrees against a load on its end
// (Euler-Eytelwein, whose law the simulator's sheath friction follows to 10 %:
// nested_tools_test.cpp, SheathCapstan).
#include <cmath>
#include <cstdio>
#include <vector>

#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "nested_tool_setup.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {
namespace {

constexpr double kPtfeOnSteelDynamic = 0.16;  // Wypych 2018, Table 11.1 (dry)
constexpr double kHydrophilicOverSteel = 1.0 / 6.0;  // Schroeder 1993, abstract

// The microcatheter of cases/neuro_coiling.case (its proximal section, 0.017" lumen) with the
// default lumen liner, and the coil's pusher (its proximal section: 0.33 mm, EI 10 N mm^2).
std::vector<ToolSpec> microcatheter_and_pusher() {
  ToolSpec pusher = testing::wire("pusher", 0.33, 10.0);
  pusher.inside = "microcatheter";
  return {testing::catheter("microcatheter", 0.8, 0.43, 8.0, ToolSpec{}.lumen_friction), pusher};
}

struct Felt {
  double hand_mN;  // at the hand (the lumen's friction added)
  double end_mN;   // at the microcatheter's tip, where the pusher leaves it
};

// The mean forces over the last 50 of 200 slipping steps one way, with `load_mN` on the end.
Felt slip(Simulator& sim, double dir, double load_mN, double theta) {
  sim.set_node_load(1, sim.rod(1).node_total() - 1, -testing::bend_exit_tangent(theta) * load_mN);
  Felt mean{0.0, 0.0};
  int count = 0;
  for (int i = 0; i < 200; ++i) {
    sim.set_insertion(1, sim.insertion_mm(1) + dir * 0.005);
    sim.step();
    if (i >= 150) {
      mean.hand_mN += sim.hand_force_mN(1);
      mean.end_mN += sim.rod(1).hand_force_mN();
      ++count;
    }
  }
  mean.hand_mN /= count;
  mean.end_mN /= count;
  return mean;
}

// Pushed and pulled through a 180 degree turn of the microcatheter (radius 20 mm), the coil's
// pusher feels a lumen friction coefficient between a sixth of the dry PTFE-on-steel one
// (Schroeder 1993's hydrophilic coat) and that one (Wypych 2018). The coefficient is the
// capstan's on the end load: mu = |ln(dF_hand / dF_end)| / theta between 50 and 150 mN on the
// pusher's end, which leaves out the load-independent push of the pusher's stiffness on the
// lumen's curvature (Schroeder's other factor of the sliding friction), printed beside it.
TEST(PublishedFriction, CoilPusherInTheMicrocathetersLinerFeelsAPublishedPtfeOnSteelCoefficient) {
  const double theta = M_PI;
  const double R = 20.0;
  TubeNetworkWall wall;
  wall.add_polyline(testing::bend_points(R, theta, 2.0, 40.0, M_PI / 720.0), 1.0, 0);
  wall.build();
  Simulator sim(wall, microcatheter_and_pusher(), Entry{{0, 0, -2}, {0, 0, 1}}, testing::precise());
  const double cath_in = 2.0 + R * theta + 8.0;
  testing::drive(sim, 0, cath_in, 0.1);
  testing::drive(sim, 1, cath_in + 6.0, 0.1);

  for (const double dir : {1.0, -1.0}) {
    const Felt low = slip(sim, dir, 50.0, theta);
    const Felt high = slip(sim, dir, 150.0, theta);
    const double mu = std::abs(std::log((high.hand_mN - low.hand_mN) / (high.end_mN - low.end_mN))) / theta;
    std::printf("pusher %s: lumen mu %.4f (published %.3f-%.2f); at 50 mN on its end %.1f mN at the hand, "
                "%.1f mN at the tip\n",
                dir > 0.0 ? "pushed" : "pulled", mu, kPtfeOnSteelDynamic * kHydrophilicOverSteel,
                kPtfeOnSteelDynamic, low.hand_mN, low.end_mN);
    EXPECT_LE(mu, kPtfeOnSteelDynamic);
    EXPECT_GE(mu, kPtfeOnSteelDynamic * kHydrophilicOverSteel);
  }
}

}  // namespace
}  // namespace cathbox::tool
