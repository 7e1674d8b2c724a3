// The bundled angioplasty case (cases/neuro_angioplasty.case + .actions) as a session in virtual
// time: the script's inflate / deflate become recorded balloon controls, the residual stenosis
// and the balloon's figures reach the metrics, and the record replays with every state hash
// matching and the same figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "session/action_script_hand.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

std::string temp_path(const std::string& name) { return fixtures::temp_path("session_test", name); }

double named(const Metrics& m, const std::string& name) {
  const std::vector<NamedMetric> all = named_metrics(m);
  const auto it = std::find_if(all.begin(), all.end(), [&](const NamedMetric& n) { return n.name == name; });
  EXPECT_NE(it, all.end()) << name;
  return it == all.end() ? -1.0 : it->value;
}

TEST(AngioplastySession, TheBundledCaseWidensTheLesionAndReplays) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  SessionCaseLoad loaded = load_session_case(dir + "neuro_angioplasty.case");
  ASSERT_TRUE(loaded.value) << loaded.error;
  std::string error;
  auto hand = ActionScriptHand::load(dir + "neuro_angioplasty.actions", *loaded.value, error);
  ASSERT_TRUE(hand) << error;
  const std::string path = temp_path("angioplasty.cbxrec");
  Metrics live;
  {
    Session s(std::move(loaded.value), std::move(hand));
    ASSERT_TRUE(s.record_to(path, error)) << error;
    while (!s.over()) s.step_virtual(1000);
    EXPECT_EQ(s.end_reason(), record::EndReason::kHandFinished);
    live = s.metrics();
  }
  EXPECT_GT(named(live, "stenosis_before_pct"), 65.0);
  EXPECT_LE(named(live, "residual_stenosis_pct"), 30.0);
  EXPECT_EQ(named(live, "balloon_inflations"), 1.0);
  EXPECT_GT(named(live, "balloon_inflated_s"), 10.0);
  EXPECT_EQ(named(live, "rupture_risk_events"), 0.0);
  // Two balloon controls (inflate, deflate) in the record.
  auto reader = RecordReader::open(path, error);
  ASSERT_TRUE(reader) << error;
  ASSERT_EQ(reader->header().tools.size(), 2u);
  EXPECT_TRUE(reader->header().tools[0].balloon.present()) << "the balloon is in the record's header";
  int balloon_controls = 0;
  TickRecord t;
  while (reader->next(t)) {
    for (std::size_t i = 0; i < t.control_count; ++i) {
      balloon_controls += t.controls[i].kind == static_cast<std::uint16_t>(ControlKind::kBalloon) ? 1 : 0;
    }
  }
  EXPECT_EQ(balloon_controls, 2);
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  EXPECT_GT(r.hashes_checked, 200);
  EXPECT_DOUBLE_EQ(*r.metrics.residual_stenosis_pct, *live.residual_stenosis_pct);
  EXPECT_EQ(*r.metrics.balloon_inflations, 1);
}

}  // namespace
}  // namespace cathbox::session
