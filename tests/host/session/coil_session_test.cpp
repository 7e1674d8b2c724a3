// A released coil in the session's scene snapshot: after `detach` the coil leaves the coil
// tool's nodes and SceneSnapshot::coils carries it, node for node where the simulator has it
// (the trainer draws it from there in the 3D view and the fluoroscopy); `load_coil` then feeds
// the case's next coil; the record (its header with the next coil, the detach_coil and
// load_coil controls) replays with every state hash matching, and its coil sleep counts in the metrics. A small analytic case (a 6.4 mm sphere on a 2 mm
// artery, microcatheter and a 20 mm coil), in virtual time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <fstream>
#include <string>

#include "session/keyboard_hand.hpp"
#include "session/metrics.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

// tests/host/session/data/coil_in_sphere.case: the sphere, its artery, the microcatheter and
// the coil tool (a 20 mm coil, then a 15 mm next_coil). session_cli_test.sh runs it too.

// The microcatheter's tip 1 mm into the sphere, the coil pushed out until its detachment zone
// is 1.5 mm past the tip, released at 2400 ms, the pusher drawn back; at 3000 ms the next coil
// (15 mm) is loaded at the hub and pushed 10 mm into the catheters; four seconds' rest
// to the end (the released coil creeps, 0.06 um a tick, until ~6 s, then sleeps).
constexpr const char* kScript = R"(0     select microcatheter
0     insert_to 21 at 20
0     select coil
0     insert_to 20.5 at 20
1200  insert_to 42.5 at 20
2400  detach
2500  insert_to 15 at 40
3000  load_coil
3000  insert_to 10 at 40
7400  end
)";

std::unique_ptr<SessionCase> sphere_case() {
  SessionCaseLoad loaded = load_session_case(std::string(CATHBOX_SOURCE_DIR) + "/tests/host/session/data/coil_in_sphere.case");
  EXPECT_TRUE(loaded) << loaded.error().message;
  return std::move(loaded.value());
}

TEST(CoilSession, AfterDetachTheSceneSnapshotHoldsTheReleasedCoilWhereTheSimulatorHasIt) {
  std::unique_ptr<SessionCase> scene = sphere_case();
  ASSERT_TRUE(scene);
  std::unique_ptr<Hand> hand = fixtures::script_hand(*scene, kScript);
  ASSERT_TRUE(hand);
  const std::string record = fixtures::temp_path("coil_session_test", "coil.cbxrec");
  std::string error;
  std::int64_t sleep_skipped = -1, sleep_wakes = -1;
  {
    Session s(std::move(scene), std::move(hand));
    const base::Status<> recording = s.record_to(record);
    ASSERT_TRUE(recording) << recording.error().message;
    // Before the release: two tools, no coil.
    s.step_virtual(2400);
    ASSERT_TRUE(s.snapshots().acquire());
    EXPECT_EQ(s.snapshots().read_slot().tool_count, 2);
    EXPECT_EQ(s.snapshots().read_slot().coil_count, 0);
    // The HUD names K (detach) while the held coil is attached, L (load) once it is released.
    EXPECT_EQ(s.snapshots().read_slot().held_tool, 1u);
    EXPECT_TRUE(s.snapshots().read_slot().held_coil_attached);
    EXPECT_FALSE(s.snapshots().read_slot().held_next_coil);
    ASSERT_EQ(s.simulator().detached_count(), 0u);
    // The release and the pusher drawn back.
    s.step_virtual(400);
    ASSERT_EQ(s.simulator().detached_count(), 1u);
    ASSERT_TRUE(s.snapshots().acquire());
    const SceneSnapshot& snap = s.snapshots().read_slot();
    EXPECT_EQ(snap.tool_count, 2) << "the released coil is not one of the tools";
    ASSERT_EQ(snap.coil_count, 1);
    const tool::Rod& coil = s.simulator().detached(0);
    const ToolView& view = snap.coils[0];
    ASSERT_EQ(view.nodes_mm.size(), coil.positions().size());
    EXPECT_GT(view.nodes_mm.size(), 30u);  // 20 mm at 0.5 mm
    double worst = 0.0;
    for (std::size_t k = 0; k < view.nodes_mm.size(); ++k) {
      worst = std::max(worst, static_cast<double>(glm::length(glm::dvec3(view.nodes_mm[k]) - coil.positions()[k])));
    }
    EXPECT_LT(worst, 1e-4) << "a snapshot node is " << worst << " mm from the simulator's";
    EXPECT_NEAR(view.radius_mm, 0.125F, 1e-6F);
    EXPECT_FALSE(view.active);
    // Every node in the sphere: the coil stayed where it was released.
    for (const glm::vec3& p : view.nodes_mm) EXPECT_LT(glm::length(p - glm::vec3(0, 0, 20)), 3.2F);
    // The pusher (the coil tool) no longer carries the coil: its tip is back in the catheter.
    EXPECT_LT(snap.tools[1].nodes_mm.back().z, 13.0F);
    EXPECT_FALSE(snap.held_coil_attached);
    EXPECT_TRUE(snap.held_next_coil);
    // The next (and last listed) coil loaded at 3000 ms: K again, no L.
    s.step_virtual(300);
    ASSERT_TRUE(s.snapshots().acquire());
    EXPECT_TRUE(s.snapshots().read_slot().held_coil_attached);
    EXPECT_FALSE(s.snapshots().read_slot().held_next_coil);
    while (!s.over()) s.step_virtual(1000);
    EXPECT_EQ(s.end_reason(), record::EndReason::kHandFinished);
    EXPECT_EQ(s.simulator().coils_loaded(1), 1u);
    EXPECT_EQ(s.simulator().rod(1).spec().detach_mm, 15.0) << "the tool carries the next coil";
    EXPECT_NEAR(s.simulator().insertion_mm(1), 10.0, 1e-9) << "pushed from the hub";
    // The coil sleep in the metrics: the simulator's own counts; the released coil came to rest
    // and slept once nothing near it moved.
    const tool::CoilSleep& sleep = s.simulator().coil_sleep();
    ASSERT_TRUE(s.metrics().coil_sleep_skipped_steps.has_value());
    ASSERT_TRUE(s.metrics().coil_sleep_wakes.has_value());
    EXPECT_EQ(*s.metrics().coil_sleep_skipped_steps, static_cast<std::int64_t>(sleep.skipped_steps()));
    EXPECT_EQ(*s.metrics().coil_sleep_wakes, static_cast<std::int64_t>(sleep.wakes()));
    EXPECT_GT(sleep.skipped_steps(), 0u) << "the released coil never slept";
    sleep_skipped = *s.metrics().coil_sleep_skipped_steps;
    sleep_wakes = *s.metrics().coil_sleep_wakes;
  }  // the record is closed
  auto reader_opened = RecordReader::open(record);
  ASSERT_TRUE(reader_opened) << reader_opened.error().message;
  auto reader = std::move(*reader_opened);
  ASSERT_EQ(reader->header().tools.size(), 2u);
  ASSERT_EQ(reader->header().tools[1].next_coils.size(), 1u) << "the next coil is in the record's header";
  EXPECT_EQ(reader->header().tools[1].next_coils[0].length_mm, 15.0);
  EXPECT_EQ(reader->header().tools[1].next_coils[0].loop_diameter_mm, 3.0);
  int detaches = 0, loads = 0;
  TickRecord t;
  while (reader->next(t)) {
    for (std::size_t i = 0; i < t.control_count; ++i) {
      detaches += t.controls[i].kind == static_cast<std::uint16_t>(ControlKind::kDetachCoil) ? 1 : 0;
      loads += t.controls[i].kind == static_cast<std::uint16_t>(ControlKind::kLoadCoil) ? 1 : 0;
    }
  }
  EXPECT_EQ(detaches, 1);
  EXPECT_EQ(loads, 1);
  const ReplayResult r = replay_record(record);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  EXPECT_GT(r.hashes_checked, 10);
  // The replay sleeps the same coil steps; the figures are named for the server and printed.
  EXPECT_EQ(r.metrics.coil_sleep_skipped_steps, sleep_skipped);
  EXPECT_EQ(r.metrics.coil_sleep_wakes, sleep_wakes);
  int named = 0;
  for (const NamedMetric& n : named_metrics(r.metrics)) {
    if (n.name == "coil_sleep_skipped_steps") named += n.value == static_cast<double>(sleep_skipped) ? 1 : 100;
    if (n.name == "coil_sleep_wakes") named += n.value == static_cast<double>(sleep_wakes) ? 1 : 100;
  }
  EXPECT_EQ(named, 2);
  EXPECT_NE(MetricsCollector::format(r.metrics).find("coil sleep            " + std::to_string(sleep_skipped) + " coil steps skipped"),
            std::string::npos);
}

// The wall forces after a release: the session's readings (TickView::contacts, what the peak
// wall force, the time above threshold and the server's trace read) cover the released coil as
// well as the case's tools. At every tick on which every rod's step converged, the wall reading
// is the largest contact force over all the snapshot's tools, and on some of those ticks the
// coil alone holds it.
class ReleasedCoilWallForces : public TickObserver {
 public:
  void observe(const TickView& v) override {
    if (v.sim.detached_count() == 0) return;
    ++ticks;
    sizes_match += v.contacts.size() == v.snapshot.tools.size() ? 1 : 0;
    const std::size_t tools = v.sim.tool_count();
    bool converged = true;
    for (std::size_t t = 0; t < v.snapshot.tools.size(); ++t) {
      const tool::Rod& rod = t < tools ? v.sim.rod(t) : v.sim.released_view(t - tools);  // as the snapshot has it
      converged = converged && (rod.converged() || rod.first_free_node() >= rod.node_total());
    }
    if (!converged) return;
    double case_tools = 0.0, coils = 0.0;
    for (std::size_t t = 0; t < v.snapshot.tools.size(); ++t) {
      for (const tool::RodContact& k : v.snapshot.tools[t].contacts) {
        double& m = t < tools ? case_tools : coils;
        m = std::max(m, k.normal_force_mN);
      }
    }
    ++checked;
    if (v.contacts.wall_mN() != std::max(case_tools, coils)) {
      ++wrong;
      if (first_wrong_us < 0) first_wrong_us = v.time_us;
    }
    coil_holds += coils > case_tools ? 1 : 0;
    coil_max_mN = std::max(coil_max_mN, coils);
  }
  int ticks = 0, sizes_match = 0, checked = 0, wrong = 0, coil_holds = 0;
  std::int64_t first_wrong_us = -1;
  double coil_max_mN = 0.0;  // the released coil's largest contact force at those ticks
};

TEST(CoilSession, TheWallForceReadingsCoverTheReleasedCoil) {
  std::unique_ptr<SessionCase> scene = sphere_case();
  ASSERT_TRUE(scene);
  std::unique_ptr<Hand> hand = fixtures::script_hand(*scene, kScript);
  ASSERT_TRUE(hand);
  Session s(std::move(scene), std::move(hand));
  ReleasedCoilWallForces forces;
  s.add_observer(forces);
  while (!s.over()) s.step_virtual(1000);
  ASSERT_GT(forces.ticks, 4900) << "the coil is released at 2400 ms of 7400";
  EXPECT_EQ(forces.sizes_match, forces.ticks) << "a reading per snapshot tool";
  EXPECT_GT(forces.checked, 0) << "no tick on which every step converged";
  EXPECT_EQ(forces.wrong, 0) << "first at " << forces.first_wrong_us << " us (of " << forces.checked << " checked)";
  EXPECT_GT(forces.coil_holds, 0) << "no checked tick on which the released coil alone presses hardest";
  EXPECT_GE(s.metrics().peak_wall_force_mN, forces.coil_max_mN) << "the peak wall force counts the coil";
}

// By keyboard (as by a box): K and L post detach_coil and load_coil for the held tool. After a
// load the new pusher starts at the hub and the hand carries on from there, wherever the key
// presses (or the box's slider) had left it; a load before a detach is refused.
// The sphere case driven by the keys: the microcatheter 21 mm in at 20 mm/s, then the coil held
// and pushed to 42.5 mm (its detachment zone 1.5 mm past the tip), the keys let go.
struct KeyboardCoil {
  KeyboardInput keys;
  Session s{sphere_case(), std::make_unique<KeyboardHand>(keys, 1e-3)};

  void push_coil_out() {
    keys.set_speeds(20.0, 0.0);
    s.step_virtual(1050);
    ASSERT_TRUE(s.post(Control::select_tool(1)));
    s.step_virtual(1);
    ASSERT_EQ(s.held_tool(), 1u);
    s.step_virtual(2125);
    keys.set_speeds(0.0, 0.0);
  }
};

TEST(CoilSession, AfterLoadCoilTheKeyboardHandCarriesOnFromTheHub) {
  KeyboardCoil run;
  ASSERT_NO_FATAL_FAILURE(run.push_coil_out());
  KeyboardInput& keys = run.keys;
  Session& s = run.s;
  ASSERT_TRUE(s.post(Control::load_coil(1)));
  s.step_virtual(2);
  EXPECT_EQ(s.simulator().coils_loaded(1), 0u) << "no load before the detach";
  ASSERT_TRUE(s.post(Control::detach_coil(1)));
  s.step_virtual(2);
  EXPECT_TRUE(s.simulator().parting(1)) << "the detachment zone parts over 0.1 s";
  EXPECT_EQ(s.simulator().detached_count(), 0u);
  s.step_virtual(100);
  ASSERT_EQ(s.simulator().detached_count(), 1u);
  keys.set_speeds(-40.0, 0.0);
  s.step_virtual(600);  // the pusher drawn back 24 mm
  keys.set_speeds(0.0, 0.0);
  s.step_virtual(1);
  const double drawn_back = s.simulator().insertion_mm(1);
  EXPECT_GT(drawn_back, 5.0) << "the hand is well away from the hub";
  ASSERT_TRUE(s.post(Control::load_coil(1)));
  s.step_virtual(5);
  ASSERT_EQ(s.simulator().coils_loaded(1), 1u);
  EXPECT_NEAR(s.simulator().insertion_mm(1), 0.0, 1e-9) << "the next coil stays at the hub, not at the hand's old place";
  keys.set_speeds(20.0, 0.0);
  s.step_virtual(500);
  EXPECT_NEAR(s.simulator().insertion_mm(1), 10.0, 0.05);
}

// A detach the hand does not wait for: the pusher drawn back at 40 mm/s right after K takes the
// detachment zone (1.5 mm past the tip) into the catheter within 0.04 s, before it has parted
// (0.1 s: Simulator::detach), so the zone stays whole, the coil comes back with its pusher, and
// the log says so; pushed out again and held still, the next detach releases it.
TEST(CoilSession, ADetachmentZoneDrawnBackBeforeItPartsKeepsItsCoil) {
  KeyboardCoil run;
  ASSERT_NO_FATAL_FAILURE(run.push_coil_out());
  KeyboardInput& keys = run.keys;
  Session& s = run.s;
  s.step_virtual(1);
  ASSERT_TRUE(s.post(Control::detach_coil(1)));
  s.step_virtual(2);
  ASSERT_TRUE(s.simulator().parting(1));
  ASSERT_TRUE(s.snapshots().acquire());
  EXPECT_TRUE(s.snapshots().read_slot().held_coil_parting) << "the HUD asks for a still pusher";
  keys.set_speeds(-40.0, 0.0);
  s.step_virtual(100);  // 4 mm back: the zone in the catheter from ~0.04 s
  keys.set_speeds(0.0, 0.0);
  s.step_virtual(200);
  EXPECT_FALSE(s.simulator().parting(1));
  EXPECT_EQ(s.simulator().detached_count(), 0u) << "released though drawn back before its zone parted";
  EXPECT_TRUE(s.simulator().carries_attached_coil(1));
  bool started = false, stopped = false, detached = false;
  LogEvent e;
  while (s.events().pop(e)) {
    const std::string text = e.text.data();
    started = started || text.find("detaching the coil of the coil") != std::string::npos;
    stopped = stopped || text.find("coil not detached: its zone was drawn back into the catheter") != std::string::npos;
    detached = detached || text.find("coil of the coil detached") != std::string::npos;
  }
  EXPECT_TRUE(started);
  EXPECT_TRUE(stopped);
  EXPECT_FALSE(detached);
  // Out again (4 mm at 20 mm/s), held, detached: released 0.1 s later.
  keys.set_speeds(20.0, 0.0);
  s.step_virtual(200);
  keys.set_speeds(0.0, 0.0);
  s.step_virtual(1);
  ASSERT_TRUE(s.post(Control::detach_coil(1)));
  s.step_virtual(110);
  EXPECT_EQ(s.simulator().detached_count(), 1u);
  while (s.events().pop(e)) detached = detached || std::string(e.text.data()).find("coil of the coil detached") != std::string::npos;
  EXPECT_TRUE(detached);
}

}  // namespace
}  // namespace cathbox::session
