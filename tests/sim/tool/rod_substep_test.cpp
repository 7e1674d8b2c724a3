// A tick whose Newton solve ends unconverged is solved again from its start in 2, then 4 equal
// sub-increments of the clamp's motion, each of dt / parts (RodSettings::substeps_max,
// sim/tool/src/rod_substep.cpp). Quasi-static: a frictionless rod's equilibrium depends on where
// the clamp is, not on how it got there, so the subdivided tick must be exactly the sub-ticks it
// stands for, and it must end at the equilibrium the slow push reaches: Lubinski's helix
// (Lubinski, Althouse & Logan, J. Petroleum Technology 14(6), 1962: a wire pushed delta past the
// closed end of a tube of length L, radial clearance r, reads F = 4 EI delta / (r^2 L); the rod
// itself against it: helical_buckling_test.cpp).
#include <algorithm>
#include <cmath>
#include <cstddef>

#include <gtest/gtest.h>

#include "closed_tube_wire.hpp"
#include "tool/rod.hpp"
#include "tool/simulator.hpp"

namespace cathbox::tool {
namespace {

using testing::kHelixContact_mm;

Rod make_wire() {
  RodSettings settings;
  settings.warm_start = 0.0;  // each solve starts from the predictor alone: the two paths compare exactly
  return testing::closed_tube_wire(settings);
}

void push(Rod& rod, const WallModel& wall, double& insertion, double target, double per_step) {
  while (insertion < target - 1e-9) {
    insertion = std::min(target, insertion + per_step);
    rod.set_boundary(insertion, 0.0);
    rod.step(1e-3, wall);
  }
}

TEST(RodSubsteps, AnUnconvergedTickIsSolvedAgainAsItsSubTicksAndEndsOnLubinskisHelix) {
  const TubeNetworkWall wall = testing::closed_helix_tube();
  Rod a = make_wire();
  Rod b = make_wire();
  a.settings().substeps_max = 1;
  b.settings().substeps_max = 1;
  double ia = 0.0;
  double ib = 0.0;
  push(a, wall, ia, kHelixContact_mm + 5.0, 0.05);  // the same history: 50 mm/s to 5 mm past the end
  push(b, wall, ib, kHelixContact_mm + 5.0, 0.05);
  // One tick pushing 0.4 mm (0.4 m/s) into the helix: its solve does not converge in one.
  constexpr double kJump_mm = 0.4;
  a.settings().substeps_max = 4;
  ia += kJump_mm;
  a.set_boundary(ia, 0.0);
  a.step(1e-3, wall);
  const int parts = a.last_substeps();
  ASSERT_GT(parts, 1) << "the tick converged whole: nothing was subdivided";
  EXPECT_TRUE(a.converged());
  for (int j = 1; j <= parts; ++j) {
    b.set_boundary(ib + kJump_mm * j / parts, 0.0);
    b.step(1e-3 / parts, wall);
  }
  ib += kJump_mm;
  ASSERT_EQ(a.node_total(), b.node_total());
  for (std::size_t k = a.first_node(); k < a.node_total(); ++k) {
    ASSERT_EQ(a.positions()[k].x, b.positions()[k].x) << "node " << k;
    ASSERT_EQ(a.positions()[k].y, b.positions()[k].y) << "node " << k;
    ASSERT_EQ(a.positions()[k].z, b.positions()[k].z) << "node " << k;
  }
  EXPECT_EQ(a.hand_force_mN(), b.hand_force_mN());
  EXPECT_EQ(a.converged(), b.converged());
  // Held, it settles on the helix 6 mm past the end.
  for (int k = 0; k < 50; ++k) a.step(1e-3, wall);
  const double expected = testing::lubinski_helix_mN(ia - kHelixContact_mm);
  EXPECT_NEAR(a.hand_force_mN() / expected, 1.0, 0.15);
}

// Without subdivision the same tick ends unconverged (the test above is not vacuous), and a
// converged tick is never solved again.
TEST(RodSubsteps, OnlyAnUnconvergedTickIsSubdivided) {
  const TubeNetworkWall wall = testing::closed_helix_tube();
  Rod rod = make_wire();
  rod.settings().substeps_max = 1;
  double insertion = 0.0;
  push(rod, wall, insertion, kHelixContact_mm + 5.0, 0.05);
  rod.set_boundary(insertion + 0.4, 0.0);
  rod.step(1e-3, wall);
  EXPECT_FALSE(rod.converged());
  EXPECT_EQ(rod.last_substeps(), 1);
  rod.settings().substeps_max = 4;
  for (int k = 0; k < 200; ++k) rod.step(1e-3, wall);  // held: every tick converges whole
  EXPECT_TRUE(rod.converged());
  EXPECT_EQ(rod.last_substeps(), 1);
}

// Joins to the wall's active set are a solve's own. A whole attempt that ended on a join (its
// last round, the round count at its limit: with 2 Newton iterations a tick, rounds raised to 4,
// 3 joins) left the join bits set, and the sub-ticks' solves added those nodes' wall terms a
// second time at their next join: the subdivided tick then missed its sub-ticks by up to 4 um.
TEST(RodSubsteps, AFailedAttemptsJoinsDoNotCarryIntoItsSubTicks) {
  const TubeNetworkWall wall = testing::closed_helix_tube();
  for (const double jump : {0.2, 0.3, 0.4, 0.6}) {
    Rod a = make_wire();
    Rod b = make_wire();
    for (Rod* r : {&a, &b}) {
      r->settings().substeps_max = 1;
      r->settings().newton_iterations = 2;
    }
    double ia = 0.0;
    double ib = 0.0;
    push(a, wall, ia, kHelixContact_mm + 3.0, 0.05);
    push(b, wall, ib, kHelixContact_mm + 3.0, 0.05);
    a.settings().substeps_max = 4;
    ia += jump;
    a.set_boundary(ia, 0.0);
    a.step(1e-3, wall);
    const int parts = a.last_substeps();
    for (int j = 1; j <= parts; ++j) {  // the sub-ticks' insertions rounded as rod_substep.cpp's
      b.set_boundary(j == parts ? ia : ib + (ia - ib) * (static_cast<double>(j) / parts), 0.0);
      b.step(1e-3 / parts, wall);
    }
    ASSERT_GT(parts, 1) << "jump " << jump << ": the tick converged whole";
    ASSERT_EQ(a.node_total(), b.node_total());
    int differ = 0;
    double most = 0.0;
    for (std::size_t k = a.first_node(); k < a.node_total(); ++k) {
      const glm::dvec3 d = a.positions()[k] - b.positions()[k];
      differ += d.x != 0.0 || d.y != 0.0 || d.z != 0.0;
      most = std::max({most, std::abs(d.x), std::abs(d.y), std::abs(d.z)});
    }
    EXPECT_EQ(differ, 0) << "jump " << jump << " parts " << parts << " largest " << most << " mm";
    EXPECT_EQ(a.hand_force_mN(), b.hand_force_mN()) << "jump " << jump;
  }
}

}  // namespace
}  // namespace cathbox::tool
