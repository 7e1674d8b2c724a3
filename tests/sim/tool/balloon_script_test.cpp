// The balloon in the case file and the action script: what parses, and one clear line
// (file:line: what) for each bad value.
#include <gtest/gtest.h>

#include <sstream>

#include "scenario/action_script.hpp"
#include "scenario/case_file.hpp"
#include "scenario/scenario_runner.hpp"
#include "tool/tube_network_wall.hpp"

namespace cathbox::tool {
namespace {

constexpr const char* kTools =
    "tube 1 0 0 -10 3 0 0 300 3\n"
    "entry 0 0 0 0 0 1\n"
    "tool cath catheter\n"
    "  section 150 od=0.9 ei=60 gj=45\n"
    "  inner_diameter 0.45\n";

std::string error_of(const std::string& balloon_line) {
  const CaseParse p = parse_case(std::string(kTools) + balloon_line + "\nend\n", "b.case");
  return p ? std::string() : p.error().message;
}

TEST(BalloonCase, ParsesTheBalloonOfACatheter) {
  const CaseParse p = parse_case(std::string(kTools) + "  balloon length=20 from_tip=3 nominal=6 burst=14 chart=2:4.6,6:5.0,14:5.5\nend\n", "b.case");
  ASSERT_TRUE(p) << p.error().message;
  const BalloonSpec& b = p->tools[0].balloon;
  EXPECT_TRUE(b.present());
  EXPECT_DOUBLE_EQ(b.length_mm, 20.0);
  EXPECT_DOUBLE_EQ(b.from_tip_mm, 3.0);
  EXPECT_DOUBLE_EQ(b.nominal_atm, 6.0);
  EXPECT_DOUBLE_EQ(b.rated_burst_atm, 14.0);
  EXPECT_EQ(b.pressure_atm, (std::vector<double>{2.0, 6.0, 14.0}));
  EXPECT_EQ(b.diameter_mm, (std::vector<double>{4.6, 5.0, 5.5}));
  EXPECT_EQ(check_tools(p->tools), "");
}

TEST(BalloonCase, BadBalloonsGiveOneLineWithFileAndLine) {
  EXPECT_EQ(error_of("  balloon length=20"), "b.case:6: balloon: length= and chart= are required");
  EXPECT_EQ(error_of("  balloon length=0 chart=6:5"), "b.case:6: balloon: length must be in (0, 100] mm");
  EXPECT_EQ(error_of("  balloon length=20 chart=6:5,4:5.2"), "b.case:6: balloon: chart pressures must increase");
  EXPECT_EQ(error_of("  balloon length=20 chart=4:5,6:4.8"), "b.case:6: balloon: chart diameters must not decrease");
  EXPECT_EQ(error_of("  balloon length=20 chart=6-5"), "b.case:6: balloon: chart point '6-5' is not PRESSURE:DIAMETER");
  EXPECT_EQ(error_of("  balloon length=20 chart=6:5 nominal=10 burst=8"), "b.case:6: balloon: burst must be in [nominal, 30] atm");
  EXPECT_EQ(error_of("  balloon length=60 from_tip=100 chart=6:5"),
            "b.case:6: balloon: does not fit on the tool (from_tip + length > tool length)");
  EXPECT_EQ(error_of("  balloon length=20 size=3 chart=6:5"),
            "b.case:6: balloon: unknown key 'size' (known: length from_tip nominal burst chart)");
  EXPECT_EQ(error_of("  balloon length=20 chart=6:5\n  balloon length=20 chart=6:5"), "b.case:7: balloon given twice");
  const CaseParse wire = parse_case("tube 1 0 0 -10 3 0 0 300 3\nentry 0 0 0 0 0 1\ntool w guidewire\n  section 200 od=0.36 ei=1 gj=1\n"
                                    "  balloon length=20 chart=6:5\nend\n", "w.case");
  ASSERT_FALSE(wire);
  EXPECT_EQ(wire.error().message, "w.case:5: balloon: only a catheter carries a balloon");
}

TEST(BalloonScript, ParsesInflateAndDeflate) {
  const ScriptParse s = parse_script("0 inflate 6 atm\n10 inflate 0.4 ml\n20 deflate\n", "a.actions");
  ASSERT_TRUE(s) << s.error().message;
  ASSERT_EQ(s->actions.size(), 3u);
  EXPECT_EQ(s->actions[0].kind, ActionKind::kInflatePressure);
  EXPECT_DOUBLE_EQ(s->actions[0].value, 6.0);
  EXPECT_EQ(s->actions[1].kind, ActionKind::kInflateVolume);
  EXPECT_DOUBLE_EQ(s->actions[1].value, 0.4);
  EXPECT_EQ(s->actions[2].kind, ActionKind::kDeflate);
}

TEST(BalloonScript, BadInflateValuesGiveOneClearLine) {
  const auto error = [](const char* text) {
    const ScriptParse s = parse_script(text, "a.actions");
    return s ? std::string() : s.error().message;
  };
  EXPECT_EQ(error("0 inflate 31 atm\n"), "a.actions:1: inflate: pressure must be in [0, 30] atm");
  EXPECT_EQ(error("0 inflate -1 atm\n"), "a.actions:1: inflate: pressure must be in [0, 30] atm");
  EXPECT_EQ(error("0 inflate x atm\n"), "a.actions:1: inflate: pressure must be in [0, 30] atm");
  EXPECT_EQ(error("0 inflate 25 ml\n"), "a.actions:1: inflate: volume must be in [0, 20] ml");
  EXPECT_EQ(error("0 select a\n5 inflate 6\n"), "a.actions:2: inflate: expected VALUE atm or VALUE ml");
  EXPECT_EQ(error("0 inflate 6 bar\n"), "a.actions:1: inflate: expected VALUE atm or VALUE ml");
  EXPECT_EQ(error("0 deflate now\n"), "a.actions:1: deflate: takes no arguments");
}

// The runner: inflate on a tool without a balloon, and a volume the balloon cannot hold.
TEST(BalloonScript, TheRunnerRefusesWhatTheBalloonCannotDo) {
  CaseParse c = parse_case(std::string(kTools) + "  balloon length=20 from_tip=3 chart=2:2.5,6:3.0\nend\n"
                           "tool wire guidewire\n  section 300 od=0.36 ei=1 gj=1\n  inside cath\nend\n", "b.case");
  ASSERT_TRUE(c) << c.error().message;
  const TubeNetworkWall wall(c->tubes);
  const auto run = [&](const char* text) {
    Simulator sim(wall, c->tools, *c->entry);
    const ScriptParse s = parse_script(text, "a.actions");
    EXPECT_TRUE(s) << s.error().message;
    std::ostringstream csv;
    ScenarioOptions o;
    o.script_name = "a.actions";
    const ScenarioResult r = run_scenario(sim, *s, o, csv);
    return std::make_pair(r, sim.balloon(0) != nullptr ? sim.balloon(0)->max_pressure_atm() : -1.0);
  };
  auto [bad_tool, p0] = run("0 select wire\n10 inflate 6 atm\n");
  EXPECT_FALSE(bad_tool.ok);
  EXPECT_EQ(bad_tool.error, "a.actions:2: inflate: tool 'wire' has no balloon");
  auto [too_much, p1] = run("0 select cath\n10 inflate 19 ml\n");
  EXPECT_FALSE(too_much.ok);
  EXPECT_EQ(too_much.error.rfind("a.actions:2: inflate: 19 ml is more than the balloon holds at 30 atm (", 0), 0u)
      << too_much.error;
  auto [good, p2] = run("0 select cath\n10 inflate 6 atm\n4000 deflate\n5000 end\n");
  EXPECT_TRUE(good.ok) << good.error;
  EXPECT_DOUBLE_EQ(p2, 6.0);
}

}  // namespace
}  // namespace cathbox::tool
