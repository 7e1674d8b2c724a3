// The seed's contact behaviours of the elastic rod: stop against a dead end while the force
// rises and pull back frees the tool; buckle from the seed; the hard limit of penetration in a
// fold; slide along a wall met at an angle; warm starts and reversal damping.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "analytic_walls.hpp"
#include "rod_test_support.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {
namespace {

using testing::insert_to;
using testing::uniform_tool;

TEST(RodBehaviour, PushIntoDeadEndStopsToolAndForceRisesThenPullBackFrees) {
  const TubeNetworkWall wall = testing::straight_tube(0.6, -5.0, 30.0);  // closed end at z = 30.6
  Rod rod(uniform_tool(120.0, 0.36, 20.0, 15.0, 1.0, 0.1));
  rod.set_entry({0, 0, 0}, {0, 0, 1});
  insert_to(rod, wall, 28.0, 0.1);
  EXPECT_NEAR(rod.hand_force_mN(), 0.0, 5.0);
  const double free_force = rod.hand_force_mN();
  double peak = free_force;
  for (double ins = 28.5; ins <= 33.0; ins += 0.5) {
    insert_to(rod, wall, ins, 0.05);
    const glm::dvec3 tip = rod.tip().position_mm;
    EXPECT_LT(tip.z, 30.6 - 0.18 + 0.02) << "tip passed the dead end at insertion " << ins;
    peak = std::max(peak, rod.hand_force_mN());
  }
  // The tool is stopped by the wall: the force at the hand has risen far above sliding.
  EXPECT_GT(rod.hand_force_mN(), 100.0);
  EXPECT_GT(peak, 10.0 * std::max(1.0, free_force));
  insert_to(rod, wall, 20.0, 0.05);
  EXPECT_LT(std::abs(rod.hand_force_mN()), 5.0);
  EXPECT_LT(rod.tip().position_mm.z, 21.0);
}

// Largest lateral offset of the inserted nodes from the z axis.
double lateral_mm(const Rod& rod) {
  double most = 0.0;
  for (std::size_t k = rod.first_free_node(); k < rod.node_total(); ++k) {
    const glm::dvec3 p = rod.positions()[k];
    most = std::max(most, std::hypot(p.x, p.y));
  }
  return most;
}

TEST(RodBehaviour, StraightToolPushedIntoADeadEndBucklesFromTheSeedAndIsNotReseededOnceBent) {
  // A straight tool in a straight tube, pushed into the closed end, buckles (the buckling seed
  // takes it off the unstable straight branch). Once bent and jammed
  // (Newtons at the hand, its edges compressed), held, it comes to rest: seeding it again every
  // compressed step kept shaking it (0.27-0.32 mm a step at 8 Newton iterations, the cap).
  const TubeNetworkWall wall = testing::straight_tube(0.6, -5.0, 30.0);  // closed end at z = 30.6
  const ToolSpec spec = uniform_tool(120.0, 0.36, 2.0, 1.5, 1.0, 0.1);
  for (const double pushed : {42.0, 45.0, 55.0}) {
    Rod rod(spec);
    rod.set_entry({0, 0, 0}, {0, 0, 1});
    insert_to(rod, wall, 31.0, 0.1);
    insert_to(rod, wall, pushed, 0.02);
    EXPECT_GT(lateral_mm(rod), 0.3) << "the seeded tool buckles, pushed to " << pushed;
    // Held 400 steps: over the last 200 no node moves more in a step than the solver's
    // convergence tolerance (2 um; the shaking this guards against was 0.27-0.32 mm a step), no
    // step runs out of iterations.
    std::vector<glm::dvec3> before;
    double moved = 0.0;
    int iterations = 0;
    for (int i = 0; i < 400; ++i) {
      rod.step(1e-3, wall);
      if (i >= 200) {
        for (std::size_t k = 0; k < before.size(); ++k) moved = std::max(moved, glm::length(rod.positions()[k] - before[k]));
        iterations = std::max(iterations, rod.last_iterations());
      }
      before.assign(rod.positions().begin(), rod.positions().end());
    }
    EXPECT_LT(moved, RodSettings{}.convergence_mm) << "a bent, held tool comes to rest, pushed to " << pushed;
    EXPECT_LT(iterations, RodSettings{}.newton_iterations) << "pushed to " << pushed;
    EXPECT_GT(rod.hand_force_mN(), 100.0) << "and stays jammed, pushed to " << pushed;
  }
}

// A short rod of one or two free nodes past the entry pushed onto a closed end: the out-of-plane test of
// the buckling seed reads 0 for it whatever its shape (a plane through the entry line holds any
// one node, and the first free node is held near the line by the clamp), so it was seeded on
// every compressed step (the stent case's bench: every such step, 68 of 14,000) and the solve
// spent its iterations taking the 10 um back out. A rod that short (<= 2 edges) is far under its
// buckling load (clamped-free Euler, pi^2 EI / (4 l^2): 49 N for this one at l = 1 mm), so it
// stays on the entry line: unseeded, nothing moves it off.
TEST(RodBehaviour, AShortRodOfOneOrTwoFreeNodesPushedOntoADeadEndIsNotSeeded) {
  const ToolSpec spec = uniform_tool(120.0, 0.36, 20.0, 15.0, 0.5, 0.1);
  for (const double end_mm : {0.0, 0.3}) {  // the tip meets the cap 0.42 mm past the tube's end
    const TubeNetworkWall wall = testing::straight_tube(0.6, -5.0, end_mm);
    Rod rod(spec);
    rod.set_entry({0, 0, 0}, {0, 0, 1});
    insert_to(rod, wall, end_mm + 0.42 + 0.01, 0.01);  // pushed on, the cap's contact compressing it
    double lateral = 0.0;
    for (int i = 0; i < 50; ++i) {
      rod.step(1e-3, wall);
      lateral = std::max(lateral, lateral_mm(rod));
    }
    const std::size_t free_nodes = rod.node_total() - rod.first_free_node();
    std::printf("tube's end %.1f mm past the entry: %zu free nodes, lateral %.3g mm, hand force %.0f mN\n", end_mm, free_nodes,
                lateral, rod.hand_force_mN());
    ASSERT_LE(free_nodes, 2U) << "the short rod this test is about";
    EXPECT_GT(rod.hand_force_mN(), 100.0) << "pushed onto the cap";
    EXPECT_LT(lateral, 1e-9) << "a rod of " << free_nodes << " free nodes stays on the entry line";
  }
}

// A V-shaped valley whose two walls meet along the y axis at an acute angle (2 x 35 degrees
// between the walls' normals and the axis): the lumen is below both planes through the origin,
// n1 = (cos a, 0, sin a), n2 = (-cos a, 0, sin a). A node in it touches both walls, as one in a
// fold of a meshed wall does (the two sides of the fold face each other, n1 . n2 = -cos 2a).
class ValleyWall final : public WallModel {
 public:
  explicit ValleyWall(double half_angle_rad)
      : n1_(std::cos(half_angle_rad), 0.0, std::sin(half_angle_rad)), n2_(-std::cos(half_angle_rad), 0.0, std::sin(half_angle_rad)) {}
  [[nodiscard]] bool probe(const WallProbe& p, WallHint&, WallContact& out) const override {
    const double d1 = -glm::dot(n1_, p.center_mm);  // distance to each wall, positive in the lumen
    const double d2 = -glm::dot(n2_, p.center_mm);
    const bool first = d1 <= d2;
    const glm::dvec3& n = first ? n1_ : n2_;
    const glm::dvec3& other = first ? n2_ : n1_;
    const double d = std::min(d1, d2);
    const double d_other = std::max(d1, d2);
    if (d - p.radius_mm > p.range_mm) return false;
    out.normal = n;
    out.distance_mm = d;
    out.point_mm = p.center_mm + n * d;
    out.segment = 0;
    out.has_second = p.second_wall && d_other - p.radius_mm < p.margin_mm;
    out.second_normal = other;
    out.second_point_mm = p.center_mm + other * d_other;
    return true;
  }

 private:
  glm::dvec3 n1_, n2_;
};

TEST(RodBehaviour, NoWallContactExceedsThePenaltyAtTheHardLimitInAFold) {
  // Pushed into the valley's apex, the tip's nodes press on both walls. The hard limit of
  // penetration (5 % of the radius) holds for both planes at once, so no contact reads more than
  // the penalty there (2e5 mN/mm x 9 um = 1.8 N for this 0.36 mm wire): projected on one plane
  // and then the other, a node pushed back across the first (the planes face each other) read
  // the penalty of that overshoot (the kinked ICA's fold: tens of newtons at the hand).
  // No buckling seed: the valley is open along its apex line, and a wire seeded once compressed
  // by 50 mN (RodSettings::buckling_strain) buckles along it instead of pressing into the apex.
  const ValleyWall wall(35.0 * M_PI / 180.0);
  RodSettings settings;
  settings.buckling_seed_mm = 0.0;
  Rod rod(uniform_tool(80.0, 0.36, 2.0, 1.5, 1.0, 0.1), settings);
  rod.set_entry({0, 0, -40}, {0, 0, 1});
  const double cap_mN = settings.contact_stiffness_mN_per_mm * settings.max_penetration_ratio * 0.18;
  double largest_mN = 0.0;
  int pressed = 0;
  double ins = 0.0;
  while (ins < 60.0) {
    ins += 0.05;
    rod.set_boundary(ins, 0.0);
    rod.step(1e-3, wall);
    for (const RodContact& c : rod.contacts()) {
      largest_mN = std::max(largest_mN, c.normal_force_mN);
      if (c.normal_force_mN > 0.5 * cap_mN) ++pressed;
    }
  }
  std::printf("valley: largest contact %.1f mN (cap %.1f mN), %d contacts above half the cap\n", largest_mN, cap_mN, pressed);
  EXPECT_GT(pressed, 0) << "the tool is pressed into the valley";
  EXPECT_LE(largest_mN, cap_mN * (1.0 + 1e-6));
}

TEST(RodBehaviour, TipMeetingWallAtAnAngleSlidesAlongIt) {
  // A tube with a 50 degree kink: the straight tool meets the far wall at an angle and follows it.
  const TubeNetworkWall wall({Tube{{0, 0, -5}, {0, 0, 20}, 1.0, 1.0, 0},
                              Tube{{0, 0, 20}, {20 * std::sin(0.87), 0, 20 + 20 * std::cos(0.87)}, 1.0, 1.0, 1}});
  ToolSpec spec = uniform_tool(150.0, 0.36, 2.0, 1.5, 1.0, 0.1);
  spec.sections.insert(spec.sections.begin(), ToolSection{100.0, 0.36, 20.0, 15.0, 0.0});
  spec.sections.back().length_mm = 30.0;
  spec.tip_spacing_mm = 0.5;
  Rod rod(spec);
  rod.set_entry({0, 0, 0}, {0, 0, 1});
  insert_to(rod, wall, 36.0, 0.1);
  std::int32_t segment = -1;
  EXPECT_GT(wall.signed_distance(rod.tip().position_mm, &segment), 0.0);
  EXPECT_EQ(segment, 1);
  EXPECT_GT(rod.tip().position_mm.x, 8.0);
  EXPECT_LT(rod.hand_force_mN(), 50.0);
}

TEST(RodBehaviour, WarmStartMeetsTheSameMotionInFewerIterations) {
  // A frictionless tool worked back and forth through a 90 degree bend at the haptic rate (3 mm
  // push-pull at 1 Hz): starting each step from half the last step's motion (the default)
  // takes fewer Newton iterations than starting from the advected positions (here 9,608 against
  // 9,864; on bench_tool's coaxial stack 3.9 against 4.9 a step), and the tool ends where it
  // does without it (both solves stop at the same convergence test).
  TubeNetworkWall wall;
  wall.add_polyline(testing::bend_points(10.0, M_PI / 2.0, 20.0, 30.0), 1.0, 0);
  wall.build();
  const ToolSpec spec = uniform_tool(150.0, 0.8, 20.0, 15.0, 1.0, 0.0);
  const auto run = [&](double warm, int& iterations) {
    RodSettings settings;
    settings.warm_start = warm;
    Rod rod(spec, settings);
    rod.set_entry({0, 0, 0}, {0, 0, 1});
    insert_to(rod, wall, 45.0, 0.05);
    iterations = 0;
    for (int i = 0; i < 2000; ++i) {
      rod.set_boundary(45.0 + 3.0 * std::sin(i * 1e-3 * 2.0 * M_PI), 0.0);
      rod.step(1e-3, wall);
      iterations += rod.last_iterations();
    }
    return rod.tip().position_mm;
  };
  int cold = 0, warm = 0;
  const glm::dvec3 tip_cold = run(0.0, cold);
  const glm::dvec3 tip_warm = run(RodSettings{}.warm_start, warm);
  EXPECT_GT(RodSettings{}.warm_start, 0.0);
  EXPECT_LT(warm, cold);
  EXPECT_LT(glm::length(tip_warm - tip_cold), 0.05);
}

TEST(RodBehaviour, AToolPushedOutOfAnyPlaneKeepsTheWarmStartWhileCompressedShortOfAJam) {
  // A tool with wall friction pushed on at 20 mm/s through two bends in different planes (so it
  // lies out of every plane through its entry and is never given a buckling seed) is compressed
  // past buckling_strain (1e-5) on most steps, far short of a jam. Starting those steps from half
  // the last motion, as the default does (a step starts cold only when seeded or after one
  // compressed past warm_start_strain), takes fewer Newton iterations than starting every
  // compressed step cold (warm_start_strain at buckling_strain: the rule before record format
  // 18, under which the ADAPT session's aspiration catheter, pushed round the siphon, went
  // unconverged on 17 % of its ticks and jammed: docs/sim-tool/convergence.md, "The warm start
  // after the seed"), and the tool ends where it ends cold.
  std::vector<glm::dvec3> path = testing::bend_points(10.0, M_PI / 2.0, 20.0, 0.0);
  const glm::dvec3 corner = path.back();
  for (int i = 1; i <= 90; ++i) {  // from +x towards +y, radius 10 mm
    const double a = M_PI / 2.0 * i / 90.0;
    path.push_back(corner + glm::dvec3{10.0 * std::sin(a), 10.0 * (1.0 - std::cos(a)), 0.0});
  }
  path.push_back(path.back() + glm::dvec3{0.0, 40.0, 0.0});
  TubeNetworkWall wall;
  wall.add_polyline(path, 1.0, 0);
  wall.build();
  const ToolSpec spec = uniform_tool(150.0, 0.8, 20.0, 15.0, 1.0, 0.3);
  constexpr double kSeedForce_mN = 50.0;  // buckling_strain's 1e-5 at the default EA, 5,000 N
  const auto run = [&](double warm, double jam_strain, int& iterations, int& compressed_steps) {
    RodSettings settings;
    settings.warm_start = warm;
    settings.warm_start_strain = jam_strain;
    Rod rod(spec, settings);
    rod.set_entry({0, 0, -20}, {0, 0, 1});
    insert_to(rod, wall, 30.0, 0.05);
    iterations = 0;
    compressed_steps = 0;
    for (int i = 1; i <= 2000; ++i) {
      rod.set_boundary(30.0 + 0.02 * i, 0.0);
      rod.step(1e-3, wall);
      iterations += rod.last_iterations();
      if (rod.hand_force_mN() > kSeedForce_mN) ++compressed_steps;
    }
    return rod.tip().position_mm;
  };
  const RodSettings defaults;
  int cold = 0, old_rule = 0, warm = 0, pushed = 0, unused = 0;
  const glm::dvec3 tip_cold = run(0.0, defaults.warm_start_strain, cold, unused);
  run(defaults.warm_start, defaults.buckling_strain, old_rule, unused);
  const glm::dvec3 tip_warm = run(defaults.warm_start, defaults.warm_start_strain, warm, pushed);
  std::printf("  Newton iterations over 2,000 steps: cold %d, cold after every compressed step %d, default %d; "
              "%d steps pushed with more than 50 mN\n", cold, old_rule, warm, pushed);
  EXPECT_GT(pushed, 1000);
  EXPECT_LT(warm, old_rule);
  EXPECT_LT(warm, cold);
  EXPECT_LT(glm::length(tip_warm - tip_cold), 0.05);
}

TEST(RodBehaviour, ReversalDampingLeavesTheToolWhereItEndsWithout) {
  // A tool with wall friction and a tip load worked back and forth (1 mm at 1 Hz) and twisted
  // through a 90 degree bend at the haptic rate, with and without halving small updates that
  // reverse the last one (RodSettings::damp_reversals): the tool ends where it ends without
  // (both runs stop on the same convergence test). Here the damping costs steps at the cap
  // (68 against 56 of 2,000; on bench_tool's separate rods it saves them: 2.2 -> 0.6 %).
  TubeNetworkWall wall;
  wall.add_polyline(testing::bend_points(10.0, M_PI / 2.0, 20.0, 30.0), 1.0, 0);
  wall.build();
  const ToolSpec spec = uniform_tool(150.0, 0.8, 20.0, 15.0, 1.0, 0.3);
  const auto run = [&](bool damp) {
    RodSettings settings;
    settings.damp_reversals = damp;
    Rod rod(spec, settings);
    rod.set_entry({0, 0, 0}, {0, 0, 1});
    insert_to(rod, wall, 45.0, 0.05);
    rod.set_node_load(rod.node_total() - 1, glm::dvec3(0.0, 0.0, -30.0));
    for (int i = 0; i < 2000; ++i) {
      rod.set_boundary(45.0 + 1.0 * std::sin(i * 1e-3 * 2.0 * M_PI), 0.3 * std::sin(i * 3e-3));
      rod.step(1e-3, wall);
    }
    return rod.tip().position_mm;
  };
  EXPECT_FALSE(RodSettings{}.damp_reversals);  // every update takes the line search instead
  EXPECT_LT(glm::length(run(true) - run(false)), 0.05);
}

// A wall beside a straight tool along +z: a ledge on its +x side that presses it (x = 0.10, the
// wire's radius 0.18) for 10 <= z <= 11.4, ending under the pressed nodes; nothing for
// 11.4 < z <= 20; and (with `clear`) a wall beyond z = 20 at x = 0.06, whose plane the tool bent
// away by the ledge takes (within the contact margin, 0.15 mm) but does not touch.
class LedgeThenClearWall final : public WallModel {
 public:
  static constexpr double kClearFromZ = 20.0;
  explicit LedgeThenClearWall(bool clear) : clear_(clear) {}
  [[nodiscard]] bool probe(const WallProbe& p, WallHint&, WallContact& out) const override {
    const double z = p.center_mm.z;
    const glm::dvec3 normal(1.0, 0.0, 0.0);
    if (z >= 10.0 && z <= 11.4) return testing::plane_contact(p, normal, 0.10, out);
    if (clear_ && z > kClearFromZ) return testing::plane_contact(p, normal, 0.06, out);
    return false;
  }

 private:
  bool clear_;
};

TEST(RodBehaviour, ANodeThatLeftTheWallIsNotHeldOnTheNextPlaneItFinds) {
  // A node's normal force is its last step's: one that left the wall (no plane at the end of a
  // step) has none. Kept from its last contact, it put the node in the next solve's active set as
  // soon as the node found a plane again, and the penalty's quadratic continued below 0 pulled
  // it there from off the wall: the dense coiling case's withdrawn pusher read -1,104.6 mN on its
  // clamp for one tick from a node 0.15 mm clear of the wall (scripts/robustness, x0.995). Here
  // the tool pressed by the ledge goes on past a wall it never touches: it moves as it does with
  // no wall there at all.
  const auto run = [](bool clear) {
    const LedgeThenClearWall wall(clear);
    Rod rod(uniform_tool(80.0, 0.36, 20.0, 15.0, 0.5, 0.1));
    rod.set_entry({0, 0, 0}, {0, 0, 1});
    std::vector<glm::dvec3> path;  // the free nodes at each step, then the hand force as (F, 0, 0)
    double pressed_mN = 0.0;
    for (double ins = 0.0; ins < 26.0;) {
      ins += 0.05;
      insert_to(rod, wall, ins, 0.05);
      for (const RodContact& c : rod.contacts()) pressed_mN = std::max(pressed_mN, c.normal_force_mN);
      path.insert(path.end(), rod.positions().begin() + static_cast<std::ptrdiff_t>(rod.first_free_node()), rod.positions().end());
      path.emplace_back(rod.hand_force_mN(), 0.0, 0.0);
    }
    EXPECT_GT(pressed_mN, 1.0) << "the ledge presses the tool";
    return path;
  };
  const std::vector<glm::dvec3> with = run(true);
  const std::vector<glm::dvec3> without = run(false);
  ASSERT_EQ(with.size(), without.size());
  double largest = 0.0;  // mm, or mN for the hand force
  std::size_t past = 0;
  for (std::size_t i = 0; i < with.size(); ++i) {
    largest = std::max(largest, glm::length(with[i] - without[i]));
    if (with[i].z > LedgeThenClearWall::kClearFromZ) ++past;
  }
  std::printf("clear wall: %zu node positions past it, largest difference %.3g (mm or mN)\n", past, largest);
  EXPECT_GT(past, 500u);
  EXPECT_LT(largest, 1e-9) << "a wall the tool does not touch moves it or reads on the hand";
}

// An end cap across +z at `cap_z` (normal +z), which the test moves between steps.
class MovingCap final : public WallModel {
 public:
  double cap_z = 0.0;
  [[nodiscard]] bool probe(const WallProbe& p, WallHint&, WallContact& out) const override {
    return testing::plane_contact(p, glm::dvec3(0.0, 0.0, 1.0), cap_z, out);
  }
};

TEST(RodBehaviour, AStepDoesNotConvergeOnANodeItLetGoUnderAPull) {
  // A short stiff wire (two free nodes, EA 5,000 N) pressed on an end cap; the cap draws back
  // 15 um. Its clamp reads the linearised equilibrium, as a coil's and a rod's among other rods do
  // (a lone rod's is also bounded by its free part's loads, which would hide the pull). The tip
  // ended the last step pressed, so the next solve starts with it held on the cap's plane, and
  // the penalty's quadratic, continued below 0, pulls it there. The wire's axial springs
  // (~2.5e6 mN/mm) let it move ~1 um, under the 2 um convergence test, and the update lets it
  // go: converged there, the clamp read the pull (the ICA-T Solumbra run drew 106-438 mN this
  // way). A node let go under more than RodSettings::release_pull_mN takes another iteration, and
  // the hand reads what it does with no cap there at all.
  const auto hand_after_cap_draws_back = [](double release_pull_mN, bool cap_there) {
    RodSettings settings;
    settings.release_pull_mN = release_pull_mN;
    settings.buckling_seed_mm = 0.0;
    settings.linearised_clamp = true;  // as a coil's, or a rod's among other rods: no bound below
    Rod rod(uniform_tool(40.0, 0.36, 20.0, 15.0, 1.0, 0.0), settings);
    rod.set_entry({0, 0, 0}, {0, 0, 1});
    MovingCap wall;
    wall.cap_z = cap_there ? 2.0 : 100.0;
    insert_to(rod, wall, 2.0 - 0.18 + 0.004, 0.01);  // the tip 4 um into the cap's contact
    double pressed_mN = 0.0;
    for (const RodContact& c : rod.contacts()) pressed_mN = std::max(pressed_mN, c.normal_force_mN);
    EXPECT_EQ(pressed_mN > 100.0, cap_there) << "the cap presses the tip";
    wall.cap_z += 0.015;
    rod.step(1e-3, wall);
    EXPECT_TRUE(rod.contacts().empty());
    return rod.hand_force_mN();
  };
  const double free_mN = hand_after_cap_draws_back(RodSettings{}.release_pull_mN, false);
  const double guarded_mN = hand_after_cap_draws_back(RodSettings{}.release_pull_mN, true);
  const double unguarded_mN = hand_after_cap_draws_back(std::numeric_limits<double>::infinity(), true);
  std::printf("cap drawn back: hand %.3f mN (no cap %.3f), converging on the release %.1f mN\n", guarded_mN, free_mN,
              unguarded_mN);
  EXPECT_NEAR(guarded_mN, free_mN, 1.0);
  EXPECT_LT(unguarded_mN, free_mN - 500.0) << "the case the guard is for: the pull read on the clamp";
}

}  // namespace
}  // namespace cathbox::tool
