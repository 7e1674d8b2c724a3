// Coaxial tools, selection and the snapshot.
#include "tool/simulator.hpp"

#include <glm/geometric.hpp>
#include <gtest/gtest.h>

#include "analytic_walls.hpp"

namespace cathbox::tool {
namespace {

std::vector<ToolSpec> coaxial_tools() {
  ToolSpec cath;
  cath.name = "cath";
  cath.kind = ToolKind::kCatheter;
  cath.sections = {ToolSection{400.0, 1.0, 30.0, 23.0, 0.0}};
  cath.inner_diameter_mm = 0.6;
  ToolSpec wire;
  wire.name = "wire";
  wire.sections = {ToolSection{500.0, 0.36, 20.0, 15.0, 0.0}, ToolSection{5.0, 0.36, 0.5, 0.4, 60.0}};
  wire.inside = "cath";
  return {cath, wire};
}

void drive(Simulator& sim, std::size_t tool, double target, double per_step) {
  while (std::abs(sim.insertion_mm(tool) - target) > 1e-9) {
    const double d = std::clamp(target - sim.insertion_mm(tool), -per_step, per_step);
    sim.set_insertion(tool, sim.insertion_mm(tool) + d);
    sim.step();
  }
}

// The wire 27 mm in, 7 mm ahead of its catheter (as the bundled coiling script holds its microwire).
struct WireAheadOfCatheter {
  TubeNetworkWall wall = testing::y_bifurcation();
  Simulator sim{wall, coaxial_tools(), Entry{{0, 0, -42}, {0, 0, 1}}};
  std::size_t cath = sim.find_tool("cath");
  std::size_t wire = sim.find_tool("wire");
  WireAheadOfCatheter() {
    drive(sim, cath, 20.0, 0.2);
    drive(sim, wire, 27.0, 0.2);
  }
};

TEST(Simulator, WireInsideCatheterFollowsItThenLeadsBeyondItsTip) {
  const TubeNetworkWall wall = testing::y_bifurcation();
  const std::vector<ToolSpec> tools = coaxial_tools();
  Simulator sim(wall, tools, Entry{{0, 0, -42}, {0, 0, 1}});
  const std::size_t cath = sim.find_tool("cath");
  const std::size_t wire = sim.find_tool("wire");
  ASSERT_EQ(sim.find_tool("none"), sim.tool_count());
  drive(sim, cath, 30.0, 0.2);
  drive(sim, wire, 20.0, 0.2);
  // Inside the catheter the wire's nodes lie on the catheter's centreline.
  std::vector<glm::dvec3> wire_nodes;
  sim.inserted_positions(wire, wire_nodes);
  ASSERT_GT(wire_nodes.size(), 5u);
  const glm::dvec3 wire_tip = wire_nodes.back();
  const glm::dvec3 on_cath = sim.rod(cath).point_at_depth(20.0, nullptr, nullptr);
  EXPECT_LT(glm::length(wire_tip - on_cath), 1e-6);
  // A straight catheter adds no friction: the wire feels only the valve on the catheter's hub
  // (to 1e-6 mN: pushed at 200 mm/s the catheter is compressed past the buckling seed's 50 mN by
  // the solver's drag and takes its 10 um offset, whose lumen friction reads ~1e-8 mN).
  EXPECT_NEAR(sim.hand_force_mN(wire), sim.valve(wire).force_mN, 1e-6);
  EXPECT_NEAR(sim.hand_force_mN(wire), kDefaultValveFriction_mN, 1e-6);
  // Pushed beyond the catheter tip, the wire leads.
  drive(sim, wire, 45.0, 0.2);
  const glm::dvec3 cath_tip = sim.tip(cath).position_mm;
  const glm::dvec3 lead = sim.tip(wire).position_mm;
  EXPECT_GT(lead.z, cath_tip.z + 10.0);
  // The wire beyond the catheter starts at the catheter's tip.
  EXPECT_LT(glm::length(sim.rod(wire).entry_point() - cath_tip), 1e-9);
}

// A wire held a node spacing ahead of its catheter, both advanced together (as the bundled
// coiling script holds its microwire 7 mm ahead of the microcatheter): its protrusion, the two
// insertions subtracted, is exact only to rounding, and its node on the catheter's tip stays held
// there, not let out of the clamp and taken back on rounding (on main it was: every release a
// step that could not converge; docs/sim-tool/convergence.md, "A node on the entry").
TEST(Simulator, ANodeOnTheCathetersTipStaysHeldWhileTheProtrusionHoldsStillToRounding) {
  WireAheadOfCatheter stack;
  Simulator& sim = stack.sim;
  const std::size_t cath = stack.cath;
  const std::size_t wire = stack.wire;
  const Rod& rod = sim.rod(wire);
  ASSERT_NEAR(rod.insertion_mm(), 7.0, 1e-12);
  bool station = false;
  for (std::size_t k = 0; k < rod.node_total(); ++k) station = station || rod.node_from_tip_mm(k) == 7.0;
  ASSERT_TRUE(station) << "no node 7 mm from the wire's tip";
  std::size_t first_free = 0;
  int past = 0, held = 0, changes = 0;
  for (int i = 1; i <= 1000; ++i) {
    sim.set_insertion(cath, 20.0 + 0.01 * i);
    sim.set_insertion(wire, 27.0 + 0.01 * i);
    sim.step();
    (rod.insertion_mm() > 7.0 ? past : held) += 1;
    if (i > 1) changes += rod.first_free_node() != first_free ? 1 : 0;
    first_free = rod.first_free_node();
  }
  EXPECT_GT(past, 0) << "the node was never past the tip by rounding: nothing tested";
  EXPECT_GT(held, 0) << "the node was never behind the tip by rounding: nothing tested";
  EXPECT_EQ(changes, 0) << "of 1000 steps " << past << " read the protrusion past 7 mm by rounding";
}

TEST(Simulator, ActiveToolSelectionAndForceLawOfTheInnerTool) {
  const TubeNetworkWall wall = testing::y_bifurcation();
  const std::vector<ToolSpec> tools = coaxial_tools();
  Simulator sim(wall, tools, Entry{{0, 0, -42}, {0, 0, 1}});
  EXPECT_EQ(sim.active_tool(), 0u);
  sim.select(1);
  EXPECT_EQ(sim.active_tool(), 1u);
  sim.select(7);  // ignored
  EXPECT_EQ(sim.active_tool(), 1u);
  drive(sim, 0, 20.0, 0.5);
  drive(sim, 1, 35.0, 0.5);
  EXPECT_DOUBLE_EQ(sim.force_law(1).insertion0_mm, 35.0);
}

// A stuck anchor is a spring in the force law only while the catheter it holds the wire to stays
// put (its insertion for the axial spring, its rotation for the twist's): the box renders a law's
// spring about a point fixed in its frame, and PassiveLaw adds the K T / 2 damper for it (Colgate
// & Schenkel 1997). Wire and catheter advanced together (the bundled coiling run's microwire and
// microcatheter at 20 mm/s), the valve on the catheter's hub moves with the wire: stated, its
// 2e4 mN/mm spring had the box render 400 mN of drag at 20 mm/s with the wire's own force 0
// (docs/session/passive-rendering.md, "Anchors on a moving catheter").
TEST(Simulator, AnAnchorOnACatheterThatMovesIsNotASpringInTheWiresForceLaw) {
  WireAheadOfCatheter stack;
  Simulator& sim = stack.sim;
  const std::size_t cath = stack.cath;
  const std::size_t wire = stack.wire;
  const RodSettings defaults;
  const double k_anchor = defaults.stick_stiffness_mN_per_mm();
  // Both held, the wire eased back 1 um (the valve's 20 mN over its 2e4 mN/mm: it sat at its
  // slip limit from the push): the valve sticks and its spring is in the law.
  sim.set_insertion(wire, 27.0 - 1e-3);
  for (int i = 0; i < 5; ++i) sim.step();
  ASSERT_TRUE(sim.valve(wire).sticking);
  EXPECT_GE(sim.force_law(wire).stiffness_mN_per_mm, k_anchor);
  // Both advanced at 20 mm/s: the valve still sticks (nothing slides through it), but it moves.
  for (int i = 1; i <= 50; ++i) {
    sim.set_insertion(cath, 20.0 + 0.02 * i);
    sim.set_insertion(wire, 27.0 - 1e-3 + 0.02 * i);
    sim.step();
    ASSERT_TRUE(sim.valve(wire).sticking) << "step " << i;
    EXPECT_LT(sim.force_law(wire).stiffness_mN_per_mm, k_anchor) << "step " << i;
  }
  // Held again: the spring is back.
  sim.step();
  EXPECT_GE(sim.force_law(wire).stiffness_mN_per_mm, k_anchor);
  // The twist the same: the valve's k r^2 while the catheter holds its turn, not while both turn.
  const double r = sim.rod(wire).radius_at_mm(0.0);
  ASSERT_TRUE(sim.valve(wire).twist_sticking);
  EXPECT_GE(sim.force_law(wire).torsion_stiffness_mNmm_per_rad, k_anchor * r * r);
  for (int i = 1; i <= 10; ++i) {
    sim.set_rotation(cath, 0.01 * i);
    sim.set_rotation(wire, 0.01 * i);
    sim.step();
    ASSERT_TRUE(sim.valve(wire).twist_sticking) << "step " << i;
    EXPECT_LT(sim.force_law(wire).torsion_stiffness_mNmm_per_rad, k_anchor * r * r) << "step " << i;
  }
}

TEST(Simulator, SnapshotCopyReusesItsStorage) {
  const TubeNetworkWall wall = testing::y_bifurcation();
  const std::vector<ToolSpec> tools = coaxial_tools();
  Simulator sim(wall, tools, Entry{{0, 0, -42}, {0, 0, 1}});
  drive(sim, 0, 30.0, 0.5);
  drive(sim, 1, 50.0, 0.5);
  Snapshot snap;
  sim.copy_snapshot(snap);
  ASSERT_EQ(snap.tools.size(), 2u);
  EXPECT_EQ(snap.tools[1].name, "wire");
  EXPECT_EQ(snap.tools[1].positions_mm.size(), snap.tools[1].tangents.size());
  EXPECT_LT(glm::length(snap.tools[1].positions_mm.back() - sim.tip(1).position_mm), 1e-9);
  EXPECT_NEAR(snap.tools[0].positions_mm.front().z, -42.0, 2.1);  // starts at the entry
  const glm::dvec3* data = snap.tools[0].positions_mm.data();
  const std::size_t capacity = snap.tools[0].positions_mm.capacity();
  sim.step();
  sim.copy_snapshot(snap);
  EXPECT_EQ(snap.tools[0].positions_mm.data(), data);
  EXPECT_EQ(snap.tools[0].positions_mm.capacity(), capacity);
  EXPECT_EQ(snap.step, sim.time_s() > 0.0 ? static_cast<std::uint64_t>(std::llround(sim.time_s() * 1000.0)) : 0u);
}

// A grip on a catheter's tip (a clot corked in an aspiration catheter, set_tip_grip) is felt at
// the hand: withdrawn along a straight tube the catheter pulls with the grip on top of what it
// needs alone (statics: the tip anchor slips at its limit, and the straight free catheter
// carries that force to the clamp); released, the pull is back to the catheter's own.
TEST(Simulator, ATipGripIsFeltAtTheHandWhenTheCatheterIsWithdrawn) {
  const TubeNetworkWall wall = testing::straight_tube(1.5, -50.0, 150.0);
  ToolSpec cath = coaxial_tools()[0];
  const std::vector<ToolSpec> tools{cath};
  const auto pull_at_the_hand = [&](double grip_mN) {
    Simulator sim(wall, tools, Entry{{0, 0, -42}, {0, 0, 1}});
    drive(sim, 0, 100.0, 0.5);
    sim.set_tip_grip(0, grip_mN);
    EXPECT_EQ(sim.tip_grip_mN(0), grip_mN);
    double pull_mN = 0.0;
    for (int i = 0; i < 500; ++i) {  // 5 mm at 10 mm/s
      sim.set_insertion(0, sim.insertion_mm(0) - 0.01);
      sim.step();
      pull_mN = -sim.hand_force_mN(0);
    }
    return pull_mN;
  };
  const double alone = pull_at_the_hand(0.0);
  const double held = pull_at_the_hand(300.0);
  EXPECT_NEAR(held - alone, 300.0, 15.0) << "alone " << alone << " mN, with a 300 mN tip grip " << held << " mN";
  Simulator sim(wall, tools, Entry{{0, 0, -42}, {0, 0, 1}});
  sim.set_tip_grip(0, -5.0);
  EXPECT_EQ(sim.tip_grip_mN(0), 0.0) << "a grip is never negative";
}

}  // namespace
}  // namespace cathbox::tool
