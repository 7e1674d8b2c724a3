#include "scenario/action_script.hpp"
#include "scenario/script_player.hpp"

#include <gtest/gtest.h>

namespace cathbox::tool {
namespace {

TEST(ActionScript, ParsesVerbsSpeedsAndDefaults) {
  const ScriptParse p = parse_script(
      "# demo\n0 select wire\n0 insert_to 120 at 25\n\n1500 rotate_by -90\t# turn\r\n2000 insert_by -5 at 2\n"
      "2500 rotate_to 45 at 90\n3000 end\n",
      "demo.actions");
  ASSERT_TRUE(p) << p.error().message;
  const auto& a = p->actions;
  ASSERT_EQ(a.size(), 6u);
  EXPECT_EQ(a[0].kind, ActionKind::kSelect);
  EXPECT_EQ(a[0].tool, "wire");
  EXPECT_EQ(a[1].kind, ActionKind::kInsertTo);
  EXPECT_DOUBLE_EQ(a[1].speed, 25.0);
  EXPECT_EQ(a[2].kind, ActionKind::kRotateBy);
  EXPECT_DOUBLE_EQ(a[2].value, -90.0);
  EXPECT_DOUBLE_EQ(a[2].speed, kDefaultRotateSpeed_deg_s);
  EXPECT_EQ(a[2].line, 5u);
  EXPECT_EQ(a[5].kind, ActionKind::kEnd);
  EXPECT_EQ(a[5].time_ms, 3000);
}

TEST(ActionScript, ParsesImagingVerbs) {
  const ScriptParse p = parse_script(
      "0 fluoro on\n100 inject 6 at 3\n150 inject 2.5\n4000 fluoro off\n4100 roadmap\n5000 carm -20 15\n"
      "5100 roadmap off\n5200 roadmap on\n5300 inject 4 at 2 conc 240\n5400 inject 3 conc 140.5\n",
      "img.actions");
  ASSERT_TRUE(p) << p.error().message;
  const auto& a = p->actions;
  ASSERT_EQ(a.size(), 10u);
  EXPECT_EQ(a[0].kind, ActionKind::kFluoro);
  EXPECT_EQ(a[0].value, 1.0);
  EXPECT_EQ(a[1].kind, ActionKind::kInject);
  EXPECT_EQ(a[1].value, 6.0);
  EXPECT_EQ(a[1].speed, 3.0);
  EXPECT_EQ(a[2].speed, kDefaultInjectRate_ml_s);
  EXPECT_EQ(a[2].concentration_mgI_ml, 0.0);  // not given: the session's default
  EXPECT_EQ(a[8].value, 4.0);
  EXPECT_EQ(a[8].speed, 2.0);
  EXPECT_EQ(a[8].concentration_mgI_ml, 240.0);
  EXPECT_EQ(a[9].speed, kDefaultInjectRate_ml_s);
  EXPECT_EQ(a[9].concentration_mgI_ml, 140.5);
  EXPECT_EQ(a[3].value, 0.0);
  EXPECT_EQ(a[4].kind, ActionKind::kRoadmap);
  EXPECT_EQ(a[4].value, 1.0);
  EXPECT_EQ(a[5].kind, ActionKind::kCArm);
  EXPECT_EQ(a[5].value, -20.0);
  EXPECT_EQ(a[5].value2, 15.0);
  EXPECT_EQ(a[6].value, 0.0);
  EXPECT_EQ(a[7].value, 1.0);
  for (const Action& action : a) EXPECT_TRUE(is_imaging(action.kind));
  EXPECT_FALSE(is_imaging(ActionKind::kInsertTo));
}

struct BadScript {
  const char* text;
  const char* error;
};

class ActionScriptErrors : public ::testing::TestWithParam<BadScript> {};

// `detach` releases the selected tool's coil: the player reports it at its millisecond, and a
// script that would detach a tool without a coil is refused before anything runs.
TEST(ActionScript, DetachActsOnTheSelectedCoil) {
  const ScriptParse s = parse_script("0 select coil\n5 detach\n", "d.actions");
  ASSERT_TRUE(s) << s.error().message;
  ASSERT_EQ(s->actions[1].kind, ActionKind::kDetach);
  const std::vector<ScriptPlayer::ToolInfo> tools{{"micro", 100.0, false}, {"coil", 200.0, true}};
  base::Result<ScriptPlayer> player = ScriptPlayer::make(*s, tools, 0, "d.actions");
  ASSERT_TRUE(player) << player.error().message;
  for (std::int64_t ms = 0; ms < 5; ++ms) EXPECT_FALSE(player->advance(ms).detach);
  const ScriptPlayer::Step step = player->advance(5);
  ASSERT_TRUE(step.detach);
  EXPECT_EQ(*step.detach, 1u);
  EXPECT_EQ(step.detach_line, 2u);
  const ScriptParse wrong = parse_script("0 select micro\n5 detach\n", "d.actions");
  ASSERT_TRUE(wrong);
  const base::Result<ScriptPlayer> refused = ScriptPlayer::make(*wrong, tools, 1, "d.actions");
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().message, "d.actions:2: detach: 'micro' carries no coil");
  EXPECT_EQ(parse_script("0 detach now\n", "d.actions").error().message,
            "d.actions:1: detach: takes no arguments (it releases the selected tool's coil)");
}

// `load_coil` after a `detach` gives the selected coil tool its next coil: the player reports
// it and starts that tool's insertion and rotation again from 0 (the new pusher at the hub),
// clamped to the next coil's limit. Refused before anything runs: on a tool without coils, with
// no further coil listed, before the present coil's detach; arguments refused by the parser.
TEST(ActionScript, LoadCoilFeedsTheNextCoilFromTheHub) {
  const ScriptParse s = parse_script("0 select coil\n0 insert_to 50 at 1000\n100 detach\n200 load_coil\n200 insert_to 900 at 1000\n",
                                     "l.actions");
  ASSERT_TRUE(s) << s.error().message;
  ASSERT_EQ(s->actions[3].kind, ActionKind::kLoadCoil);
  ScriptPlayer::ToolInfo coil{"coil", 2000.0, true, false, {700.0}};
  const std::vector<ScriptPlayer::ToolInfo> tools{{"micro", 100.0, false}, coil};
  base::Result<ScriptPlayer> player = ScriptPlayer::make(*s, tools, 0, "l.actions");
  ASSERT_TRUE(player) << player.error().message;
  for (std::int64_t ms = 0; ms < 200; ++ms) EXPECT_FALSE(player->advance(ms).load_coil);
  EXPECT_EQ(player->insertion_mm(1), 50.0);
  const ScriptPlayer::Step step = player->advance(200);
  ASSERT_TRUE(step.load_coil);
  EXPECT_EQ(*step.load_coil, 1u);
  EXPECT_EQ(step.load_coil_line, 4u);
  EXPECT_EQ(player->insertion_mm(1), 1.0) << "from 0 at the hub, one millisecond at 1000 mm/s";
  for (std::int64_t ms = 201; ms < 2000; ++ms) player->advance(ms);
  EXPECT_EQ(player->insertion_mm(1), 700.0) << "clamped to the next coil's limit";
  // Refusals, each one line naming the script line.
  const auto refused = [&](const char* text, std::vector<ScriptPlayer::ToolInfo> with) {
    const ScriptParse p = parse_script(text, "l.actions");
    EXPECT_TRUE(p) << p.error().message;
    const base::Result<ScriptPlayer> made = ScriptPlayer::make(*p, with, 0, "l.actions");
    EXPECT_FALSE(made);
    return made ? std::string() : made.error().message;
  };
  EXPECT_EQ(refused("0 select micro\n5 load_coil\n", tools), "l.actions:2: load_coil: 'micro' carries no coil");
  EXPECT_EQ(refused("0 select coil\n5 load_coil\n", tools), "l.actions:2: load_coil: the coil of 'coil' is not detached yet");
  EXPECT_EQ(refused("0 select coil\n5 detach\n6 load_coil\n7 detach\n8 load_coil\n", tools),
            "l.actions:5: load_coil: 'coil' has no further coil (the case lists 1 after the first)");
  EXPECT_EQ(parse_script("0 load_coil 2\n", "l.actions").error().message,
            "l.actions:1: load_coil: takes no arguments (it loads the selected coil tool's next coil)");
}

// The thrombectomy verbs act on the tool selected when they come: `aspiration` on one the case
// gives a vacuum source, `balloon_guide` on one with a balloon. Any other is refused at load with
// its line (in a session it was refused only when due, and the run went on without a vacuum).
TEST(ActionScript, ThrombectomyVerbsMeetTheirDeviceOnTheSelectedTool) {
  ScriptPlayer::ToolInfo aspiration{"aspiration", 1000.0, false, false, {}, true};
  ScriptPlayer::ToolInfo guide{"guide", 1000.0, false, true, {}, false};
  const std::vector<ScriptPlayer::ToolInfo> tools{guide, aspiration, {"microcatheter", 1500.0, false}};
  const auto made = [&](const char* text) {
    const ScriptParse p = parse_script(text, "t.actions");
    EXPECT_TRUE(p) << p.error().message;
    const base::Result<ScriptPlayer> player = ScriptPlayer::make(*p, tools, 0, "t.actions");
    return player ? std::string("ok") : player.error().message;
  };
  EXPECT_EQ(made("0 balloon_guide inflate\n5 select aspiration\n6 aspiration on\n7 aspiration off\n"), "ok");
  EXPECT_EQ(made("0 select aspiration\n1 select microcatheter\n2 aspiration on\n"),
            "t.actions:3: aspiration: tool 'microcatheter' has no vacuum source (the case's `aspiration` names the catheter that has)");
  EXPECT_EQ(made("0 aspiration on\n"),
            "t.actions:1: aspiration: tool 'guide' has no vacuum source (the case's `aspiration` names the catheter that has)");
  EXPECT_EQ(made("0 select aspiration\n1 balloon_guide inflate\n"), "t.actions:2: balloon_guide: tool 'aspiration' has no balloon");
}

TEST_P(ActionScriptErrors, NameFileAndLine) {
  const ScriptParse p = parse_script(GetParam().text, "s.actions");
  ASSERT_FALSE(p);
  EXPECT_EQ(p.error().message, GetParam().error);
}

INSTANTIATE_TEST_SUITE_P(
    Bad, ActionScriptErrors,
    ::testing::Values(
        BadScript{"0 jump 3\n", "s.actions:1: unknown verb 'jump' (known: select insert_to insert_by rotate_to rotate_by end fluoro inject carm roadmap detach load_coil inflate deflate aspiration balloon_guide)"},
        BadScript{"0 fluoro maybe\n", "s.actions:1: fluoro: expected 'on' or 'off'"},
        BadScript{"0 roadmap now\n", "s.actions:1: roadmap: expected nothing, 'on' or 'off'"},
        BadScript{"0 inject 0\n", "s.actions:1: inject: volume must be in (0, 100] mL"},
        BadScript{"0 inject 6 by 3\n", "s.actions:1: inject: expected 'at RATE' and/or 'conc MGI_PER_ML' (in that order, each once), got 'by'"},
        BadScript{"0 inject 6 conc 300 at 3\n", "s.actions:1: inject: expected 'at RATE' and/or 'conc MGI_PER_ML' (in that order, each once), got 'at'"},
        BadScript{"0 inject 6 at 3 at 4\n", "s.actions:1: inject: expected 'at RATE' and/or 'conc MGI_PER_ML' (in that order, each once), got 'at'"},
        BadScript{"0 inject 6 conc 0\n", "s.actions:1: inject: concentration must be in (0, 1000] mgI/mL"},
        BadScript{"0 inject 6 at 3 conc 1200\n", "s.actions:1: inject: concentration must be in (0, 1000] mgI/mL"},
        BadScript{"0 inject 6 at 3 conc\n", "s.actions:1: inject: expected VOLUME_ML [at RATE_ML_PER_S] [conc MGI_PER_ML]"},
        BadScript{"0 inject 6 at 50\n", "s.actions:1: inject: rate must be in (0, 30] mL/s"},
        BadScript{"0 carm 30\n", "s.actions:1: carm: expected LAO_DEG CRANIAL_DEG (negative for RAO / caudal)"},
        BadScript{"0 carm 130 0\n", "s.actions:1: carm: LAO/RAO angle must be within +-120 degrees"},
        BadScript{"0 carm 30 -70\n", "s.actions:1: carm: cranial/caudal angle must be within +-60 degrees"},
        BadScript{"10 insert_to 5\n5 insert_to 6\n", "s.actions:2: time 5 ms is before the previous action"},
        BadScript{"-1 end\n", "s.actions:1: time '-1' must be a whole number of milliseconds in [0, 3600000]"},
        BadScript{"1.5 end\n", "s.actions:1: time '1.5' must be a whole number of milliseconds in [0, 3600000]"},
        BadScript{"0 insert_to\n", "s.actions:1: insert_to: expected VALUE [at SPEED]"},
        BadScript{"0 insert_to 5 by 3\n", "s.actions:1: insert_to: expected 'at SPEED', got 'by'"},
        BadScript{"0 insert_to 5 at 0\n", "s.actions:1: insert_to: speed must be in (0, 1000]"},
        BadScript{"0 insert_to -5\n", "s.actions:1: insert_to: value out of range"},
        BadScript{"0 rotate_by inf\n", "s.actions:1: rotate_by: 'inf' is not a finite number"},
        BadScript{"0 end\n1 insert_to 3\n", "s.actions:2: action after 'end'"},
        BadScript{"0\n", "s.actions:1: missing verb after the time"},
        BadScript{"0 select\n", "s.actions:1: select: expected one tool name"}));

}  // namespace
}  // namespace cathbox::tool
