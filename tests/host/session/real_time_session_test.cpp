// A session run in real time (Session::start, its own haptic thread) on a virtual clock: a tick
// that stalls the loop makes it drop ticks, and the run keeps the count in its metrics (text,
// named) and its record's end block, which a replay reads back. A run in virtual time has none;
// one paced from outside (the trainee page's worker) keeps what its pacer told.
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <thread>

#include "session/clock.hpp"
#include "session/metrics.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

using fixtures::load;
using fixtures::script_hand;

constexpr const char* kScript = "0 select guidewire\n0 insert_to 40 at 30\n2000 end\n";

// Moves the loop's clock on by `stall_us` inside one tick (a step that took that long).
struct Stall final : TickObserver {
  VirtualClock& clock;
  std::int64_t at_tick;
  std::int64_t stall_us;
  Stall(VirtualClock& c, std::int64_t tick, std::int64_t us) : clock(c), at_tick(tick), stall_us(us) {}
  void observe(const TickView& view) override {
    if (view.tick == at_tick) clock.advance_us(stall_us);
  }
};

// The y-bifurcation case under kScript, in real time on `clock` when one is given.
std::unique_ptr<Session> scripted_session(VirtualClock* clock) {
  SessionOptions options;
  options.real_time_clock = clock;
  auto scene = load("y_bifurcation.case");
  auto hand = script_hand(*scene, kScript);
  return std::make_unique<Session>(std::move(scene), std::move(hand), options);
}

// Runs `s` on its own haptic thread to its end.
void run_real_time(Session& s) {
  s.start();
  while (!s.over()) std::this_thread::yield();
  s.stop();
}

std::optional<double> named(const Metrics& m, const std::string& name) {
  const std::vector<NamedMetric> all = named_metrics(m);
  const auto it = std::find_if(all.begin(), all.end(), [&](const NamedMetric& n) { return n.name == name; });
  return it == all.end() ? std::nullopt : std::optional<double>(it->value);
}

TEST(RealTimeSession, AStalledTickDropsTicksThatTheMetricsAndTheRecordKeep) {
  VirtualClock clock;
  const std::unique_ptr<Session> run = scripted_session(&clock);
  Session& s = *run;
  const std::string path = fixtures::temp_path("real_time_session_test", "stalled.cbxrec");
  const base::Status<> recording = s.record_to(path);
  ASSERT_TRUE(recording) << recording.error().message;
  Stall stall(clock, 1000, 30'000);  // tick 1000 takes 30 ms
  s.add_observer(stall);
  run_real_time(s);
  ASSERT_TRUE(s.recorder()->close()) << s.recorder()->error();
  // 30 ticks late after the stall: 4 caught up (HapticPacer), 26 dropped; the script still runs
  // its 2000 ticks.
  EXPECT_EQ(s.ticks(), 2000);
  EXPECT_EQ(s.dropped_ticks(), 26);
  const Metrics& live = s.metrics();
  ASSERT_TRUE(live.haptic_dropped_ticks);
  EXPECT_EQ(*live.haptic_dropped_ticks, 26);
  EXPECT_NEAR(*live.haptic_dropped_pct(), 100.0 * 26 / 2026, 1e-9);
  EXPECT_NE(MetricsCollector::format(live).find("haptic ticks dropped  26 (1.28 % of the run's real time)"), std::string::npos)
      << MetricsCollector::format(live);
  EXPECT_EQ(named(live, "haptic_dropped_ticks"), 26.0);

  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.matched()) << r.error;
  ASSERT_TRUE(r.end && r.end->haptic_dropped_ticks);
  EXPECT_EQ(*r.end->haptic_dropped_ticks, 26);
  EXPECT_EQ(r.metrics.haptic_dropped_ticks, 26);  // the rig's figure, as the record says
  EXPECT_EQ(named(r.metrics, "haptic_dropped_ticks"), 26.0);
  EXPECT_DOUBLE_EQ(r.metrics.tip_path_mm, live.tip_path_mm);
}

TEST(RealTimeSession, ARunOnTimeDropsNoneAndARunInVirtualTimeHasNoFigure) {
  VirtualClock clock;
  const std::unique_ptr<Session> on_time = scripted_session(&clock);
  run_real_time(*on_time);
  ASSERT_TRUE(on_time->metrics().haptic_dropped_ticks);
  EXPECT_EQ(*on_time->metrics().haptic_dropped_ticks, 0);

  const std::unique_ptr<Session> in_virtual_time = scripted_session(nullptr);
  Session& virtual_run = *in_virtual_time;
  const std::string path = fixtures::temp_path("real_time_session_test", "virtual.cbxrec");
  ASSERT_TRUE(virtual_run.record_to(path));
  while (!virtual_run.over()) virtual_run.step_virtual(1000);
  ASSERT_TRUE(virtual_run.recorder()->close());
  EXPECT_FALSE(virtual_run.metrics().haptic_dropped_ticks);
  EXPECT_EQ(MetricsCollector::format(virtual_run.metrics()).find("haptic ticks dropped"), std::string::npos);
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.matched()) << r.error;
  ASSERT_TRUE(r.end);
  EXPECT_FALSE(r.end->haptic_dropped_ticks);
  EXPECT_FALSE(r.metrics.haptic_dropped_ticks);
  EXPECT_FALSE(named(r.metrics, "haptic_dropped_ticks"));
}

// The trainee page's worker paces the session itself (in virtual time inside) and tells it the
// ticks its clock dropped: the run keeps the last total told, as its own thread's.
TEST(RealTimeSession, ARunPacedOutsideKeepsTheDropsItsPacerTold) {
  const std::unique_ptr<Session> run = scripted_session(nullptr);
  Session& s = *run;
  const std::string path = fixtures::temp_path("real_time_session_test", "paced.cbxrec");
  ASSERT_TRUE(s.record_to(path));
  s.note_paced_drops(0);
  s.step_virtual(500);
  s.note_paced_drops(12);
  s.step_virtual(500);
  // The live frame's figure: the drops so far, in the published snapshot's metrics.
  s.snapshots().acquire();
  EXPECT_EQ(s.snapshots().read_slot().metrics.haptic_dropped_ticks, 12);
  EXPECT_EQ(s.snapshots().read_slot().metrics.haptic_ticks, 1000);
  s.note_paced_drops(19);
  while (!s.over()) s.step_virtual(1000);
  ASSERT_TRUE(s.recorder()->close());
  EXPECT_EQ(s.metrics().haptic_dropped_ticks, 19);
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.matched()) << r.error;
  EXPECT_EQ(r.metrics.haptic_dropped_ticks, 19);
  EXPECT_NEAR(*r.metrics.haptic_dropped_pct(), 100.0 * 19 / 2019, 1e-9);
}

}  // namespace
}  // namespace cathbox::session
