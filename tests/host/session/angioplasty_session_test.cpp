// The bundled angioplasty case (cases/neuro_angioplasty.case + .actions) as a session in virtual
// time: the script's inflate / deflate become recorded balloon controls, the residual stenosis
// and the balloon's figures reach the metrics, and the record replays with every state hash
// matching and the same figures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
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

// The bundled angioplasty case with its action script as the hand (null when either fails).
struct CaseAndHand {
  std::unique_ptr<SessionCase> scene;
  std::unique_ptr<Hand> hand;
};
CaseAndHand angioplasty_case() {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  SessionCaseLoad loaded = load_session_case(dir + "neuro_angioplasty.case");
  EXPECT_TRUE(loaded) << loaded.error().message;
  if (!loaded) return {};
  std::string error;
  auto script = ActionScriptHand::load(dir + "neuro_angioplasty.actions", *loaded.value());
  EXPECT_TRUE(script) << (script ? "" : script.error().message);
  if (!script) return {};
  auto hand = std::move(*script);
  return {std::move(loaded.value()), std::move(hand)};
}

TEST(AngioplastySession, TheBundledCaseWidensTheLesionAndReplays) {
  auto [scene, hand] = angioplasty_case();
  ASSERT_TRUE(scene && hand);
  std::string error;
  const std::string path = temp_path("angioplasty.cbxrec");
  Metrics live;
  {
    Session s(std::move(scene), std::move(hand));
    const base::Status<> recording = s.record_to(path);
    ASSERT_TRUE(recording) << recording.error().message;
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
  auto reader_opened = RecordReader::open(path);
  ASSERT_TRUE(reader_opened) << reader_opened.error().message;
  auto reader = std::move(*reader_opened);
  ASSERT_EQ(reader->header().tools.size(), 2u);
  EXPECT_TRUE(reader->header().tools[0].balloon.present()) << "the balloon is in the record's header";
  int balloon_controls = 0;
  std::uint64_t last_hash = 0;
  TickRecord t;
  while (reader->next(t)) {
    if (t.state_hash) last_hash = *t.state_hash;
    for (std::size_t i = 0; i < t.control_count; ++i) {
      balloon_controls += t.controls[i].kind == static_cast<std::uint16_t>(ControlKind::kBalloon) ? 1 : 0;
    }
  }
  EXPECT_EQ(balloon_controls, 2);
  std::printf("last recorded state hash %016llx\n", static_cast<unsigned long long>(last_hash));
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  EXPECT_GT(r.hashes_checked, 200);
  EXPECT_DOUBLE_EQ(*r.metrics.residual_stenosis_pct, *live.residual_stenosis_pct);
  EXPECT_EQ(*r.metrics.balloon_inflations, 1);
}

// The walls the simulator used at each tick, as observers see them.
class WallSwapsSeen : public TickObserver {
 public:
  void observe(const TickView& view) override { swaps.push_back(view.sim.wall_swaps()); }
  std::vector<std::uint64_t> swaps;  // per tick
};

TEST(AngioplastySession, TheSnapshotsWallGenerationChangesExactlyAtTheSwapTick) {
  auto [scene, hand] = angioplasty_case();
  ASSERT_TRUE(scene && hand);
  Session s(std::move(scene), std::move(hand));
  WallSwapsSeen seen;
  s.add_observer(seen);
  EXPECT_EQ(s.wall_surface(), nullptr) << "the case's own surface is the wall before any swap";
  std::uint64_t generation = 0;
  std::int64_t first_swap_tick = -1;
  int changes = 0;
  // One tick at a time up to two swaps: the snapshot after tick n carries the walls swapped in
  // by tick n, no sooner, no later.
  while (!s.over() && changes < 2) {
    ASSERT_EQ(s.step_virtual(1), 1);
    s.snapshots().acquire();
    const SceneSnapshot& snap = s.snapshots().read_slot();
    ASSERT_EQ(snap.tick, static_cast<std::int64_t>(seen.swaps.size()));
    ASSERT_EQ(snap.wall_generation, seen.swaps.back()) << "tick " << snap.tick - 1;
    if (snap.wall_generation != generation) {
      EXPECT_EQ(snap.wall_generation, generation + 1);
      generation = snap.wall_generation;
      if (changes++ == 0) first_swap_tick = snap.tick - 1;
      const std::shared_ptr<const tool::WallSurface> surface = s.wall_surface();
      ASSERT_NE(surface, nullptr);
      EXPECT_GT(surface->mesh.triangle_count(), 1000u);
      ASSERT_EQ(surface->model.segments.size(), s.scene().world->source_model()->segments.size());
    }
  }
  ASSERT_EQ(changes, 2) << "the inflation widens the lumen twice or more";
  // The first wall is due 300 ticks after the balloon first moved the lumen, which is after the
  // inflation starts (11.5 s in the script).
  EXPECT_GT(first_swap_tick, 11'500 + 300);
  // The widened model is wider than the case's at the lesion.
  const std::shared_ptr<const tool::WallSurface> surface = s.wall_surface();
  const vessel::VesselModel& before = *s.scene().world->source_model();
  double widened_mm = 0.0;
  for (std::size_t g = 0; g < before.segments.size(); ++g) {
    for (std::size_t i = 0; i < before.segments[g].points.size(); ++i) {
      widened_mm = std::max(widened_mm, surface->model.segments[g].points[i].radius_mm - before.segments[g].points[i].radius_mm);
    }
  }
  EXPECT_GT(widened_mm, 0.3);
}

}  // namespace
}  // namespace cathbox::session
