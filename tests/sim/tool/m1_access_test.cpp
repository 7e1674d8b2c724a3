// The microwire's way to the left M1 in cases/neuro_thrombectomy_m1.case (issue 30): the
// case's 45 degree tip turned a quarter turn in the supraclinoid ICA passes the posterior
// communicating artery's mouth and runs the M1 into the superior M2; unturned it takes the
// PCom into the posterior cerebral artery (the case's PCom is nearly the ICA's straight
// continuation: docs/session/thrombectomy.md). The bundled access script
// (cases/neuro_thrombectomy_m1_access.actions) relies on the first.
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "scenario/scenario_runner.hpp"

namespace cathbox::tool {
namespace {

// The microwire alone (the catheters parked in the guide), turned to `rotation_deg` at
// 110 mm and pushed on to 140 mm at 5 mm/s, as the access script does; its tip's segment.
std::int32_t wire_tip_segment_after(int rotation_deg) {
  const CaseParse c = load_case(CATHBOX_SOURCE_DIR "/cases/neuro_thrombectomy_m1.case");
  EXPECT_TRUE(c) << c.error().message;
  const std::string text =
      "0 select guide\n0 insert_to 25 at 25\n0 select aspiration\n0 insert_to 20 at 20\n"
      "0 select microcatheter\n0 insert_to 22 at 20\n0 select microwire\n0 insert_to 40 at 20\n"
      "1000 insert_to 110 at 20\n4500 rotate_to " + std::to_string(rotation_deg) + " at 180\n"
      "6500 insert_to 140 at 5\n12500 end\n";
  const ScriptParse s = parse_script(text, "m1_access.actions");
  EXPECT_TRUE(s) << (s ? "" : s.error().message);
  if (!c || !s) return -1;
  WorldBuild world = build_world(*c);
  EXPECT_TRUE(world) << world.error().message;
  if (!world) return -1;
  Simulator sim((*world)->wall(), c->tools, (*world)->entry());
  ScenarioOptions options;
  options.every_ms = 1000;
  options.script_name = "m1_access.actions";
  std::ostringstream csv;
  const ScenarioResult r = run_scenario(sim, *s, options, csv);
  EXPECT_TRUE(r.ok) << r.error;
  return sim.tip_segment(sim.find_tool("microwire"));
}

// cases/neuro.hclm: 22 left_middle_cerebral_m1, 23 its superior M2, 33 left_posterior_cerebral_p2.
TEST(M1Access, AQuarterTurnBeforeTheTerminusTakesTheWireIntoTheM1) {
  const std::int32_t seg = wire_tip_segment_after(90);
  EXPECT_TRUE(seg == 22 || seg == 23) << "segment " << seg;
}

TEST(M1Access, UnturnedTheWireTakesThePComIntoThePosteriorCerebral) {
  const std::int32_t seg = wire_tip_segment_after(0);
  EXPECT_NE(seg, 22);
  EXPECT_NE(seg, 23);
  EXPECT_EQ(seg, 33) << "segment " << seg;
}

}  // namespace
}  // namespace cathbox::tool
