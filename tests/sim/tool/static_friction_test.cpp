// Coulomb static friction on a wall (issue 29 item 6: a released coil resting on the sac must
// come to rest). A short free rod lies on a flat wall and is loaded on every node by a force at
// an angle theta to the wall's normal: the same as the rod's weight on a wall inclined at theta.
// The analytic reference is Coulomb's law: the rod sticks while the tangential load is under
// mu times the normal one, tan theta < mu, and slides above it.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "rod_test_support.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {
namespace {

// The wall z = 0, the lumen above it.
class FlatWall final : public WallModel {
 public:
  [[nodiscard]] bool probe(const WallProbe& p, WallHint&, WallContact& out) const override {
    if (p.center_mm.z - p.radius_mm > p.range_mm) return false;
    out.point_mm = {p.center_mm.x, p.center_mm.y, 0.0};
    out.normal = {0.0, 0.0, -1.0};
    out.distance_mm = p.center_mm.z;
    out.segment = 0;
    return true;
  }
};

constexpr double kMu = 0.3;
constexpr double kLoad_mN = 0.5;  // per node
constexpr double kRadius = 0.15;  // a 0.3 mm coil
constexpr double kDt = 1e-3;

struct Creep {
  double last_step_mm = 0.0;  // the largest node move over the last step
  double total_mm = 0.0;      // the largest node move from the start of loading
};

// A 10 mm rod detached on the wall, loaded at theta to the normal for `steps` steps; with a
// `lift_every` > 0, the load is taken off for one step in every `lift_every` (the node then
// rests on its plane at a gap of about 0, touched again by the next load: a pile's chatter).
Creep load_on_wall(double theta_rad, int steps, int lift_every = 0) {
  ToolSpec spec = testing::uniform_tool(20.0, 2.0 * kRadius, 20.0, 15.0, 0.5, kMu);
  spec.detach_mm = 10.0;
  spec.drag_mN_s_per_mm2 = 1e-2;
  const FlatWall wall;
  Rod rod(spec, testing::static_settings());
  rod.set_entry({0.0, 0.0, kRadius}, {1.0, 0.0, 0.0});
  testing::insert_to(rod, wall, 12.0, 0.5);
  Rod coil = rod.split_distal(10.0);
  const std::size_t n = coil.positions().size();
  const glm::dvec3 load = kLoad_mN * glm::dvec3(std::sin(theta_rad), 0.0, -std::cos(theta_rad));
  const std::vector<glm::dvec3> start(coil.positions().begin(), coil.positions().end());
  Creep c;
  for (int i = 0; i < steps; ++i) {
    const std::vector<glm::dvec3> before(coil.positions().begin(), coil.positions().end());
    const bool lifted = lift_every > 0 && i % lift_every == lift_every - 1;
    for (std::size_t k = 0; k < n; ++k) coil.set_node_load(k, lifted ? glm::dvec3(0.0) : load);
    coil.step(kDt, wall);
    c.last_step_mm = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
      c.last_step_mm = std::max(c.last_step_mm, glm::length(coil.positions()[k] - before[k]));
      c.total_mm = std::max(c.total_mm, glm::length(coil.positions()[k] - start[k]));
    }
  }
  return c;
}

// NotYet: both fail on the simulator as it is (the slip limit is mu times the last step's normal
// force: a node pressed afresh slides its first step nearly free; 24 um, and 1.9 mm over 80
// touches). The fix (build/tail3_static_friction_fix.diff on r-tail3: mu times the larger of the
// last step's force and the penalty's at the assembly) passes them, but fails
// RodBehaviour.NoWallContactExceedsThePenaltyAtTheHardLimitInAFold (no contact over half the
// cap) and Coiling.TriaxialStackReachesTheAneurysmNeckByTheScriptedActionFile (0.56 mm, not
// under 0.5); it is not in yet. Coulomb's law checked where the solve converges (the limit from
// the iterate's normal force when that moves the solution past the convergence test; r-static,
// docs/sim-tool/convergence.md, "Coulomb's law within the step") passes the first and those two,
// and holds each of the second's touches to its stick spring's stretch (45 um over 80: a load
// taken off in one step leaves it), but moves the runs tuned to one path off it: at record format
// 42 the rigid dead end (108.2 mN in a tick), the dense coiling case, ADAPT M1, the M1 stent
// retriever, Solumbra M1 and a coil-sleep test fail with it (convergence.md, "Again at record
// format 42"); not in either.
TEST(StaticFriction, DISABLED_NotYetARodOnAWallInclinedUnderTheFrictionAngleComesToRest) {
  const double theta = 0.8 * std::atan(kMu);  // tan theta = 0.24 < mu = 0.3
  const Creep c = load_on_wall(theta, 400);
  // At rest: under the sleep's stillness test (coil_sleep.cpp: 0.01 um a tick).
  EXPECT_LT(c.last_step_mm, 1e-5) << "total " << c.total_mm;
  EXPECT_LT(c.total_mm, 0.002);  // a stuck node moves by its stick spring's stretch alone (under 1 um)
}

TEST(StaticFriction, DISABLED_NotYetARodPressedAgainAndAgainUnderTheFrictionAngleStaysPut) {
  const Creep c = load_on_wall(0.8 * std::atan(kMu), 400, 5);
  EXPECT_LT(c.total_mm, 0.002);  // 80 touches afresh, each held by Coulomb's law
}

TEST(StaticFriction, ARodOnAWallInclinedOverTheFrictionAngleSlides) {
  const double theta = 1.25 * std::atan(kMu);  // tan theta = 0.38 > mu
  const Creep c = load_on_wall(theta, 400);
  EXPECT_GT(c.last_step_mm, 1e-3);
  EXPECT_GT(c.total_mm, 1.0);
}

}  // namespace
}  // namespace cathbox::tool
