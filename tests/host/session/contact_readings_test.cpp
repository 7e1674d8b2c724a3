// ContactReadings (the wall forces the metrics and events read): a tool's reading comes from a
// step whose solve converged, and is kept over a step that ran out of iterations; a tool with
// no free node reads nothing. A default 0.014" guidewire pushed through a 60 degree kink of a
// 1 mm tube and into its closed end, with one Newton iteration a step so that both kinds of
// step occur, in virtual time.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "session/contact_readings.hpp"
#include "scenario/case_file.hpp"
#include "tool/simulator.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::session {
namespace {

// The reading the snapshot's contacts of one tool give, as taken at a converged step.
ContactReadings::Reading from_contacts(const tool::Rod& rod, const tool::ToolSnapshot& t) {
  ContactReadings::Reading r;
  for (const tool::RodContact& k : t.contacts) {
    r.wall_mN = std::max(r.wall_mN, k.normal_force_mN);
    if (k.node + ContactReadings::kTipNodes >= rod.node_total()) {
      r.tip_in_contact = true;
      r.tip_mN = std::max(r.tip_mN, k.normal_force_mN);
    }
  }
  return r;
}

TEST(ContactReadings, ConvergedStepsAreReadAndUnconvergedOnesKeepTheLastReading) {
  tool::TubeNetworkWall wall;
  wall.add_tube(tool::Tube{{0, 0, -5}, {0, 0, 20}, 1.0, 1.0, 0});
  wall.add_tube(tool::Tube{{0, 0, 20}, {20, 0, 32}, 1.0, 1.0, 1});
  wall.build();
  const std::vector<tool::ToolSpec> tools = {tool::default_guidewire()};
  tool::RodSettings settings;
  settings.newton_iterations = 1;
  tool::Simulator sim(wall, tools, tool::Entry{{0, 0, 0}, {0, 0, 1}}, settings);
  ContactReadings readings(1);
  tool::Snapshot snap;
  // Nothing inserted: no free node, a zero reading (not one kept from before).
  sim.step();
  sim.copy_snapshot(snap);
  readings.update(sim, snap);
  EXPECT_EQ(readings.tool(0).wall_mN, 0.0);
  EXPECT_EQ(readings.held_ticks(0), 0);
  int converged = 0, kept = 0, tip = 0;
  ContactReadings::Reading last;
  for (int i = 1; i <= 3000; ++i) {
    sim.set_insertion(0, std::min(45.0, 0.02 * i));  // 20 mm/s, into the closed end at ~44 mm
    sim.step();
    sim.copy_snapshot(snap);
    readings.update(sim, snap);
    const ContactReadings::Reading& r = readings.tool(0);
    const ContactReadings::Reading want = sim.rod(0).converged() ? from_contacts(sim.rod(0), snap.tools[0]) : last;
    converged += sim.rod(0).converged() && want.wall_mN > 0.0 ? 1 : 0;
    kept += sim.rod(0).converged() ? 0 : 1;
    tip += sim.rod(0).converged() && want.tip_in_contact ? 1 : 0;
    ASSERT_EQ(r.wall_mN, want.wall_mN) << "step " << i;
    ASSERT_EQ(r.tip_in_contact, want.tip_in_contact) << "step " << i;
    ASSERT_EQ(r.tip_mN, want.tip_mN) << "step " << i;
    EXPECT_EQ(readings.wall_mN(), r.wall_mN);
    last = r;
  }
  EXPECT_GT(converged, 0) << "no converged step with a contact";
  EXPECT_GT(kept, 0) << "no unconverged step";
  EXPECT_GT(tip, 0) << "no converged step with the tip on the wall";
  EXPECT_EQ(readings.held_ticks(0), kept);
}

}  // namespace
}  // namespace cathbox::session
