// The session end to end in virtual time: a case run by an action script and recorded replays
// with every state hash matching; a record whose inputs were changed does not; controls posted
// from another thread are applied at a tick boundary, recorded and replayed; the keyboard hand
// drives the held tool; the run ends for the reasons it should.
#include <gtest/gtest.h>

#include <filesystem>
#include <thread>

#include "session/action_script_hand.hpp"
#include "session/keyboard_hand.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "scenario/action_script.hpp"
#include "record_tamper.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

using fixtures::load;
using fixtures::script_hand;

std::string temp_path(const std::string& name) { return fixtures::temp_path("session_test", name); }

constexpr const char* kLeftBranch =
    "0 select guidewire\n0 insert_to 40 at 30\n1400 rotate_to 360 at 180\n2500 insert_to 95 at 20\n5500 end\n";

// Runs the y-bifurcation script recorded to `path`; returns the session's metrics.
Metrics record_left_branch(const std::string& path) {
  auto scene = load("y_bifurcation.case");
  auto hand = script_hand(*scene, kLeftBranch);
  Session s(std::move(scene), std::move(hand));
  std::string error;
  const base::Status<> recording = s.record_to(path);
  EXPECT_TRUE(recording) << recording.error().message;
  while (!s.over()) s.step_virtual(1000);
  EXPECT_EQ(s.end_reason(), record::EndReason::kHandFinished);
  EXPECT_EQ(s.ticks(), 5500);  // `end` at 5500 ms stops before that tick
  return s.metrics();
}

TEST(Session, AScriptedRunReplaysWithEveryHashMatching) {
  const std::string path = temp_path("left.cbxrec");
  const Metrics live = record_left_branch(path);
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  EXPECT_EQ(r.ticks, 5500);
  EXPECT_EQ(r.recorded_ticks, 5500);
  EXPECT_EQ(r.hashes_checked, 55);
  ASSERT_TRUE(r.end);
  EXPECT_EQ(r.end->reason, record::EndReason::kHandFinished);
  // The same metrics from the replay as from the run.
  EXPECT_DOUBLE_EQ(r.metrics.tip_path_mm, live.tip_path_mm);
  EXPECT_EQ(r.metrics.wall_contacts, live.wall_contacts);
  EXPECT_DOUBLE_EQ(r.metrics.peak_wall_force_mN, live.peak_wall_force_mN);
  EXPECT_GT(live.tip_path_mm, 80.0);
  // Two runs of the same script write the same ticks (only the start time differs).
  const std::string again = temp_path("left_again.cbxrec");
  (void)record_left_branch(again);
  std::string error;
  auto a_opened = RecordReader::open(path);
  auto b_opened = RecordReader::open(again);
  ASSERT_TRUE(a_opened) << a_opened.error().message;
  ASSERT_TRUE(b_opened) << b_opened.error().message;
  auto a = std::move(*a_opened);
  auto b = std::move(*b_opened);
  TickRecord ta;
  TickRecord tb;
  while (a->next(ta)) {
    ASSERT_TRUE(b->next(tb));
    ASSERT_EQ(ta.tools, tb.tools);
    ASSERT_EQ(ta.state_hash, tb.state_hash);
  }
}

// Re-writes a record with one input changed by 1 um at `tick`.
std::string tamper(const std::string& path, std::int64_t tick) {
  const std::string out_path = temp_path("tampered.cbxrec");
  testing::tamper_record(path, out_path, tick);
  return out_path;
}

TEST(Session, ARecordWithChangedInputsDoesNotReplay) {
  const std::string path = temp_path("to_tamper.cbxrec");
  (void)record_left_branch(path);
  const ReplayResult r = replay_record(tamper(path, 3000));
  ASSERT_TRUE(r.error.empty()) << r.error;
  ASSERT_TRUE(r.mismatch);
  EXPECT_EQ(r.mismatch->tick, 3099);  // the first hash after the change
  EXPECT_NE(r.mismatch->recorded, r.mismatch->replayed);
  EXPECT_EQ(r.ticks, 3100);  // stopped there
}

TEST(Session, ControlsFromAnotherThreadAreAppliedRecordedAndReplayed) {
  auto scene = load("neuro.case");  // a catheter with a guidewire inside
  ASSERT_EQ(scene->spec.tools.size(), 2U);
  KeyboardInput keys;
  auto hand = std::make_unique<KeyboardHand>(keys, 1e-3);
  Session s(std::move(scene), std::move(hand));
  const std::string path = temp_path("controls.cbxrec");
  std::string error;
  const base::Status<> recording = s.record_to(path);
  ASSERT_TRUE(recording) << recording.error().message;
  ASSERT_EQ(s.held_tool(), 0U);
  keys.set_speeds(20.0, 0.0);
  s.step_virtual(300);  // the catheter goes 6 mm in
  std::thread ui([&s] { ASSERT_TRUE(s.post(Control::select_next_tool())); });
  ui.join();
  EXPECT_EQ(s.held_tool(), 0U);  // not before the next tick
  s.step_virtual(1);
  EXPECT_EQ(s.held_tool(), 1U);
  s.step_virtual(199);  // now the guidewire moves, the catheter stays
  ASSERT_TRUE(s.post(Control::select_tool(1)));  // already held: dropped, not recorded
  ASSERT_TRUE(s.post(Control::select_tool(0)));
  s.step_virtual(100);
  s.end_run();
  s.step_virtual(1);
  ASSERT_TRUE(s.over());
  EXPECT_EQ(s.metrics().tool_changes, 2);
  EXPECT_NEAR(s.simulator().insertion_mm(0), 6.0 + 2.0, 0.05);  // 300 + 100 ticks at 20 mm/s
  EXPECT_NEAR(s.simulator().insertion_mm(1), 4.0, 0.05);        // 200 ticks
  // In the record (written to its end once closed): two select controls, at ticks 300 and
  // 500, as the tools they chose.
  ASSERT_TRUE(s.recorder()->close());
  auto r_opened = RecordReader::open(path);
  ASSERT_TRUE(r_opened) << r_opened.error().message;
  auto r = std::move(*r_opened);
  TickRecord t;
  std::vector<std::pair<std::int64_t, int>> selects;
  while (r->next(t)) {
    for (std::size_t i = 0; i < t.control_count; ++i) selects.emplace_back(t.tick, t.controls[i].payload[0]);
  }
  EXPECT_EQ(selects, (std::vector<std::pair<std::int64_t, int>>{{300, 1}, {500, 0}}));
  ASSERT_TRUE(r->end());
  EXPECT_EQ(r->end()->reason, record::EndReason::kEndedByUser);
  const ReplayResult replayed = replay_record(path);
  EXPECT_TRUE(replayed.matched()) << replayed.error;
  EXPECT_EQ(replayed.metrics.tool_changes, 2);
  EXPECT_EQ(replayed.ticks, 600);
}

TEST(Session, TheRunEndsAtItsTimeLimitAndAReplayRefusesControls) {
  auto scene = load("y_bifurcation.case");
  KeyboardInput keys;
  SessionOptions options;
  options.max_ticks = 250;
  Session s(std::move(scene), std::make_unique<KeyboardHand>(keys, 1e-3), options);
  const std::string path = temp_path("limit.cbxrec");
  std::string error;
  const base::Status<> recording = s.record_to(path);
  ASSERT_TRUE(recording) << recording.error().message;
  EXPECT_EQ(s.step_virtual(1000), 250);
  EXPECT_TRUE(s.over());
  EXPECT_EQ(s.end_reason(), record::EndReason::kTimeLimit);
  ASSERT_TRUE(s.recorder()->close());
  auto opened = Replay::open(path);
  ASSERT_TRUE(opened) << opened.error().message;
  auto& replay = *opened;
  EXPECT_FALSE(replay->session().post(Control::select_tool(0)));
  replay->step(-1);
  EXPECT_TRUE(replay->result().matched());
  EXPECT_EQ(replay->result().ticks, 250);
}

TEST(Session, ABadCaseOrScriptIsOneLineNamingTheFile) {
  const SessionCaseLoad missing = load_session_case("/no/such.case");
  EXPECT_FALSE(missing);
  EXPECT_EQ(missing.error().message, "/no/such.case:0: cannot open file");
  auto scene = load("y_bifurcation.case");
  std::string error;
  const tool::ScriptParse parsed = tool::parse_script("0 select catheter\n", "bad.actions");
  ASSERT_TRUE(parsed);
  const auto bad = ActionScriptHand::make(*parsed, "bad.actions", ActionScriptHand::tool_infos(*scene), 0);
  ASSERT_FALSE(bad);
  EXPECT_EQ(bad.error().message, "bad.actions:1: select: the case has no tool 'catheter' (tools: guidewire)");
}

}  // namespace
}  // namespace cathbox::session
