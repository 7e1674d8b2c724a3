// A wire pushed into a closed, frictionless tube buckles into a helix against its wall. Lubinski,
// Althouse & Logan, "Helical buckling of tubing sealed in packers", J. Petroleum Technology
// 14(6), 1962: a helix of pitch p holds an axial force F = 8 pi^2 EI / p^2. Its wire is longer
// than the tube it lies in by the factor sqrt(1 + (2 pi r / p)^2), r the radial clearance (tube
// radius minus wire radius); for small (2 pi r / p) the tube shortens the wire by the strain
// (2 pi r / p)^2 / 2 = r^2 F / (4 EI) (the same relation as Lubinski's length change without
// the tubing's weight). A wire pushed delta past the closed end of a tube of length L
// therefore reads at the hand F = 4 EI delta / (r^2 L), growing linearly with the push.
//
// This is the reference for the dead end of issue 29 (tests/host/session/data/dead_end.case, a
// 0.014" wire of EI 40 N mm^2 in a tube of radius 2 mm): a uniform wire 10 mm past its end reads
// 2.4 N, 58 mm past (the script's 260 mm) 13.9 N. The case's wire has a soft 50 mm tip, which
// folds back at the closed end, so its shaft is 8.2 mm past the end: 2.0 N, 2.4 N with the wall's
// friction while pushing in (tests/host/session/hand_force_replay_test.cpp, DeadEndHelix).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include <glm/geometric.hpp>

#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "closed_tube_wire.hpp"
#include "tool/rod.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {
namespace {

TEST(RodValidation, WirePushedIntoAClosedTubeBucklesIntoLubinskisHelix) {
  const TubeNetworkWall wall = testing::closed_helix_tube();
  Rod rod = testing::closed_tube_wire();
  const double contact_mm = testing::kHelixContact_mm;
  const double per_mm = testing::lubinski_helix_mN(1.0);  // mN per mm pushed
  double insertion = 0.0;
  const auto push_to = [&](double target, double per_step) {
    while (insertion < target - 1e-9) {
      insertion = std::min(target, insertion + per_step);
      rod.set_boundary(insertion, 0.0);
      rod.step(1e-3, wall);
    }
  };
  push_to(contact_mm - 4.0, 0.05);  // 50 mm/s to 4 mm short of the end
  double force_at[2] = {0.0, 0.0};
  const double deltas[2] = {5.0, 10.0};
  for (int i = 0; i < 2; ++i) {
    push_to(contact_mm + deltas[i], 0.01);  // then 10 mm/s
    for (int k = 0; k < 50; ++k) rod.step(1e-3, wall);  // held 50 ms
    force_at[i] = rod.hand_force_mN();
    const double expected = per_mm * deltas[i];
    std::printf("pushed %.0f mm past the end: hand force %.0f mN, Lubinski's helix %.0f mN\n", deltas[i], force_at[i],
                expected);
    EXPECT_NEAR(force_at[i] / expected, 1.0, 0.15) << "pushed " << deltas[i] << " mm past the end";
  }
  // The helix's axial stiffness: the force's growth between the two pushes.
  const double slope = (force_at[1] - force_at[0]) / (deltas[1] - deltas[0]);
  std::printf("helix stiffness %.0f mN/mm, Lubinski's %.0f mN/mm\n", slope, per_mm);
  EXPECT_NEAR(slope / per_mm, 1.0, 0.2);
}


// The wall's friction on the helix, to first order in mu. Mitchell ("Frictional forces in helical
// buckling of tubing", SPE Drilling Engineering 1(6), 1986) takes the friction along the tube's
// axis only; pushed in, the helix's contacts also travel round the wall as its pitch shortens,
// and Coulomb's friction opposes that slip too. Derived here by virtual work: the hand's power is
// the stored energy's rate plus the friction's dissipation, and the stored energy is stationary
// at the frictionless equilibrium, so to first order in mu the friction adds to the frictionless
// force F0 the dissipation per push, evaluated on the frictionless helix:
//   F - F0 = mu w L * min_c integral_0^1 sqrt(x^2 + ((x + c) / alpha)^2) dx,
// w = r F0^2 / (4 EI) the contact load per length, alpha = r sqrt(F0 / (2 EI)) the helix's angle
// to the axis (Lubinski), x the place along the helix from the closed end (0) to the entry (1).
// Per unit push a point at x slides x along the axis (the strain alpha^2 / 2 is uniform) and
// (x + c) / alpha round the tube (its angle round, alpha x L / r, grows with alpha); the whole
// helix may also turn (c): an isotropic wire's bend turns round its straight part at no cost, and
// its far end sits near the cap's pole (0.28 mm off the axis), so nothing holds its phase and the
// friction's torque balance sets c, where the dissipation is least. Taken along the axis only, the
// integral is 1/2: F - F0 = F0 mu delta / (2 r), Mitchell's formula to first order. The helix's
// contacts travel round 2-4 times as far as along it here, so the excess is that much larger.
// Tolerance 15 %, the rod's own agreement with the frictionless helix (above); mu 0.01 keeps the
// terms of second order in mu to a few per cent.
double first_order_excess_mN(double f0_mN, double mu) {
  const double ei = testing::kHelixWireEi_Nmm2 * 1000.0;
  const double r = testing::kHelixClearance_mm;
  const double alpha = r * std::sqrt(f0_mN / (2.0 * ei));
  const double w = r * f0_mN * f0_mN / (4.0 * ei);
  constexpr int kCells = 2000;
  double least = 1e300;
  for (int i = 0; i <= 200; ++i) {  // c from -1 (held at the entry) to 0 (held at the far end)
    const double c = -static_cast<double>(i) / 200.0;
    double sum = 0.0;
    for (int k = 0; k < kCells; ++k) {
      const double x = (k + 0.5) / kCells;
      sum += std::hypot(x, (x + c) / alpha) / kCells;
    }
    least = std::min(least, sum);
  }
  return mu * w * testing::kHelixContact_mm * least;
}

TEST(RodValidation, TheWallsFrictionRoundTheTubeRaisesTheHelixsForceByItsVirtualWork) {
  constexpr double kMu = 0.01;
  const TubeNetworkWall wall = testing::closed_helix_tube();
  for (const double delta : {5.0, 12.0}) {
    double force[2] = {0.0, 0.0};
    for (int with_friction = 0; with_friction < 2; ++with_friction) {
      Rod rod = testing::closed_tube_wire({}, with_friction != 0 ? kMu : 0.0);
      const double target = testing::kHelixContact_mm + delta;
      for (double insertion = 0.0; insertion < target - 1e-9;) {
        insertion = std::min(target, insertion + 0.03);  // 30 mm/s, the dead-end script's
        rod.set_boundary(insertion, 0.0);
        rod.step(1e-3, wall);
      }
      force[with_friction] = rod.hand_force_mN();
    }
    const double excess = force[1] - force[0];
    const double expected = first_order_excess_mN(force[0], kMu);
    const double axial_only = force[0] * kMu * delta / (2.0 * testing::kHelixClearance_mm);
    std::printf("pushed %.0f mm past the end: %.0f mN frictionless, %.0f mN at mu %.2f: excess %.1f mN, virtual work "
                "%.1f mN (along the axis only, Mitchell's to first order, %.1f mN)\n",
                delta, force[0], force[1], kMu, excess, expected, axial_only);
    EXPECT_NEAR(excess / expected, 1.0, 0.15) << "pushed " << delta << " mm past the end";
  }
}

// The dead end's wire (tests/host/session/data/dead_end.case): a 0.014" wire with a soft 50 mm
// tip curved 45 degrees over its last 3 mm, friction 0.08, in the tube of radius 2 mm closed at
// 200 mm, entering along its axis.
ToolSpec dead_end_wire() {
  ToolSpec spec;
  spec.name = "guidewire";
  spec.sections = {ToolSection{1750.0, 0.36, 40.0, 31.0, 0.0}, ToolSection{35.0, 0.36, 3.0, 2.3, 0.0},
                   ToolSection{12.0, 0.36, 0.3, 0.23, 0.0}, ToolSection{3.0, 0.36, 0.3, 0.23, 45.0}};
  spec.friction = 0.08;
  return spec;
}

// The same wire pushed at 30 mm/s to 260 mm, its shaft 8 mm past the end. Its tip's curve lies in
// one plane through the tube's axis, and nothing in the round tube breaks that symmetry: the
// rod's buckling seed (a compressed rod that is straight gets a tiny lateral offset) skipped a
// rod already bent, so the wire buckled flat, every node in the tip's plane (|y| exactly 0),
// lying along the wall between S-shaped crossings, and read 6,079 mN. A real wire is not
// perfectly flat; seeded out of its plane it goes helical round the wall (Lubinski, Althouse &
// Logan 1962): 3,298 mN (3,889 while the seed waited for 2.5 N of compression: below). Every
// node of the helix is off the tip's plane by up to the clearance.
TEST(RodBehaviour, APreCurvedWirePushedIntoAClosedTubeBucklesOutOfItsTipsPlane) {
  const TubeNetworkWall wall = testing::straight_tube(2.0, -10.0, 200.0);
  const std::vector<ToolSpec> tools{dead_end_wire()};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
  sim.select(0);
  for (double insertion = 0.0; insertion < 260.0;) {
    insertion = std::min(260.0, insertion + 0.03);
    sim.set_insertion(0, insertion);
    sim.step(1e-3);
  }
  const Rod& rod = sim.rod(0);
  const auto x = rod.positions();
  double off_plane_mm = 0.0;
  for (std::size_t k = rod.first_free_node(); k < x.size(); ++k) off_plane_mm = std::max(off_plane_mm, std::abs(x[k].y));
  std::printf("farthest node off the tip's plane %.3f mm; hand force %.0f mN\n", off_plane_mm, sim.hand_force_mN(0));
  EXPECT_GT(off_plane_mm, 0.5 * testing::kHelixClearance_mm);
}

// A wire buckled in one plane of a round tube with no weight is held in that plane by nothing:
// the flat buckle, each crossing from wall to wall in line contact (Holmes, Domokos, Schmitt &
// Szeberenyi, Comput Methods Appl Mech Eng 170, 1999), carries pi^2/3 = 3.3 times Lubinski's
// helix force for the same push, and the force that keeps a compressed rod lying on one side of
// a tube, Dawson & Paslay's 2 sqrt(EI w sin(theta) / r) (J Petroleum Technology 36(10), 1984),
// is zero without a weight w. So the dead end's wire, its tip's curve in one plane, leaves that
// plane as it buckles: by half the clearance within 10 mm of push after its own hand force first
// passes the clamped-clamped Euler load of the tube's 200 mm, 4 pi^2 EI / L^2 = 39.5 mN (the largest
// any end support gives; the solver's drag floor slows the out-of-plane growth). While the rod
// seeded its imperfection only at an edge strain of 5e-4 (2.5 N), the wire here stayed flat past
// 240 mm (the session's dead end to 253.5 mm, 1.8 N at the hand, then snapped to the helix, 610 mN
// in one tick).
TEST(RodBehaviour, APreCurvedWireLeavesItsTipsPlaneAsItBucklesInAClosedTube) {
  const TubeNetworkWall wall = testing::straight_tube(2.0, -10.0, 200.0);
  const std::vector<ToolSpec> tools{dead_end_wire()};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
  sim.select(0);
  const double euler_mN = 4.0 * M_PI * M_PI * testing::kHelixWireEi_Nmm2 * 1000.0 / (200.0 * 200.0);
  double past_euler_at = -1.0, off_plane_at = -1.0;
  for (double insertion = 0.0; insertion < 240.0 && off_plane_at < 0.0;) {
    insertion = std::min(240.0, insertion + (insertion < 180.0 ? 0.1 : 0.03));  // then 30 mm/s, the script's
    sim.set_insertion(0, insertion);
    sim.step(1e-3);
    const Rod& rod = sim.rod(0);
    if (past_euler_at < 0.0 && rod.hand_force_mN() > euler_mN) past_euler_at = insertion;
    const auto x = rod.positions();
    for (std::size_t k = rod.first_free_node(); k < x.size(); ++k) {
      if (std::abs(x[k].y) > 0.5 * testing::kHelixClearance_mm) off_plane_at = insertion;
    }
  }
  std::printf("own hand force past Euler's %.1f mN at %.2f mm; off the tip's plane by half the clearance at %.2f mm\n",
              euler_mN, past_euler_at, off_plane_at);
  ASSERT_GT(past_euler_at, 0.0);
  ASSERT_GT(off_plane_at, 0.0) << "flat to 240 mm";
  EXPECT_LT(off_plane_at - past_euler_at, 10.0);
}

// The dead end's wire (tests/host/session/data/dead_end.case: a 0.014" wire with a soft 50 mm
// tip, friction 0.08) pushed 58 mm past the closed end of the 4 mm tube at 30 mm/s. Folded by the
// helix, its soft tip is pressed onto its own shaft; without contacts of a lone tool with
// itself it passed through it (parts 5-15 mm from the tip 0.03-0.2 mm from the shaft's axis,
// the wire 0.36 mm thick). Parts of the wire more than 5 mm apart along it stay a wire's
// diameter apart, less the 10 % overlap the coils are held to.
TEST(RodBehaviour, AWireFoldedInADeadEndDoesNotPassThroughItself) {
  const TubeNetworkWall wall = testing::straight_tube(2.0, -10.0, 200.0);
  const std::vector<ToolSpec> tools{dead_end_wire()};
  Simulator sim(wall, tools, Entry{{0, 0, 0}, {0, 0, 1}});
  sim.select(0);
  double closest_mm = 1e9;
  double closest_at_mm = 0.0;
  std::vector<double> arc;
  for (double insertion = 0.0; insertion < 260.0;) {
    insertion = std::min(260.0, insertion + 0.03);
    sim.set_insertion(0, insertion);
    sim.step(1e-3);
    if (insertion < 200.0) continue;
    const Rod& rod = sim.rod(0);
    const auto x = rod.positions();
    arc.assign(x.size(), 0.0);
    for (std::size_t k = 1; k < x.size(); ++k) arc[k] = arc[k - 1] + glm::length(x[k] - x[k - 1]);
    for (std::size_t a = rod.first_free_node(); a < x.size(); ++a) {
      for (std::size_t b = a + 1; b < x.size(); ++b) {
        if (arc[b] - arc[a] < 5.0) continue;
        const double d = glm::length(x[a] - x[b]);
        if (d < closest_mm) {
          closest_mm = d;
          closest_at_mm = insertion;
        }
      }
    }
  }
  std::printf("closest parts of the wire 5 mm or more apart along it: %.3f mm (pushed to %.2f mm)\n", closest_mm,
              closest_at_mm);
  EXPECT_GT(closest_mm, 0.9 * 0.36) << "pushed to " << closest_at_mm << " mm";
  EXPECT_GT(sim.hand_force_mN(0), 1000.0) << "jammed";
}

}  // namespace
}  // namespace cathbox::tool
