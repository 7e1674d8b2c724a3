// The fluoroscopy unit inside the session, in virtual time: an action script's imaging verbs
// press the pedal, inject through the catheter and capture the roadmap; the metrics count what
// happened (fluoroscopy time = pedal time, contrast volume, runs, DAP); the record replays with
// every hash matching, the hashes cover the unit, and the renderer's view carries the images'
// inputs.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "session/action_script_hand.hpp"
#include "session/fluoro_controls.hpp"
#include "session/fluoro_switches.hpp"
#include "session/keyboard_hand.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "scenario/action_script.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

using fixtures::load;
using fixtures::script_hand;

std::string temp_path(const std::string& name) { return fixtures::temp_path("fluoro_session_test", name); }

// The catheter 100 mm up the descending aorta; the pedal down from 1000 to 5000 ms; 6 mL at
// 3 mL/s from 2500 ms (over by 4500); the roadmap taken with the pedal up.
constexpr const char* kAngio =
    "0 select catheter\n0 insert_to 100 at 100\n1000 fluoro on\n2500 inject 6 at 3\n5000 fluoro off\n"
    "5100 roadmap\n5300 end\n";

std::vector<std::string> drain(EventLog& log) {
  std::vector<std::string> out;
  LogEvent e;
  while (log.pop(e)) out.emplace_back(e.text.data());
  return out;
}

TEST(FluoroSession, AScriptedAngiogramCountsPedalTimeContrastAndOneRun) {
  const std::string path = temp_path("angio.cbxrec");
  auto scene = load("neuro.case");
  Session s(std::move(scene), script_hand(*load("neuro.case"), kAngio));
  std::string error;
  const base::Status<> recording = s.record_to(path);
  ASSERT_TRUE(recording) << recording.error().message;
  ASSERT_NE(s.fluoro(), nullptr);
  s.step_virtual(999);  // before the pedal: the figures are there, all zero
  EXPECT_EQ(s.metrics().fluoroscopy_time_s, 0.0);
  EXPECT_EQ(s.metrics().fluoroscopy_runs, 0);
  while (!s.over()) s.step_virtual(1000);
  EXPECT_EQ(s.end_reason(), record::EndReason::kHandFinished);
  const Metrics& m = s.metrics();
  ASSERT_TRUE(m.fluoroscopy_time_s && m.contrast_volume_ml && m.fluoroscopy_runs && m.dose_area_product_mGy_cm2);
  EXPECT_NEAR(*m.fluoroscopy_time_s, 4.0, 1e-9);  // pedal down at tick 1000, up at tick 5000
  EXPECT_NEAR(*m.contrast_volume_ml, 6.0, 1e-9);
  EXPECT_EQ(*m.fluoroscopy_runs, 1);
  EXPECT_GT(*m.dose_area_product_mGy_cm2, 0.0);
  const flow::Fluoroscope& scope = s.fluoro()->fluoroscope();
  EXPECT_EQ(scope.metrics().pulses, 60);  // 4 s at 15 pulses/s
  EXPECT_TRUE(scope.image().last_image_hold());
  EXPECT_GE(scope.image().roadmap_pulse, 0);  // the run's peak, taken with the pedal up
  const std::vector<std::string> events = drain(s.events());
  EXPECT_NE(std::find_if(events.begin(), events.end(),
                         [](const std::string& e) { return e.starts_with("inject 6.0 mL at 3.0 mL/s from the catheter's tip"); }),
            events.end());
  // Every contrast cell has a place on the centrelines; the view carries the image's inputs.
  ASSERT_FALSE(s.fluoro_cells().empty());
  SnapshotExchange<SceneSnapshot>& x = s.snapshots();
  (void)x.acquire();
  const FluoroView& v = x.read_slot().fluoro;
  EXPECT_TRUE(v.available);
  EXPECT_EQ(v.image.pulse, 59);
  EXPECT_EQ(v.image.run, 1);
  EXPECT_EQ(v.iodine_mgI_ml.size(), s.fluoro_cells().size());
  EXPECT_EQ(v.mask_iodine_mgI_ml.size(), s.fluoro_cells().size());
  ASSERT_EQ(v.roadmap_iodine_mgI_ml.size(), s.fluoro_cells().size());
  EXPECT_GT(*std::max_element(v.roadmap_iodine_mgI_ml.begin(), v.roadmap_iodine_mgI_ml.end()), 1.0F);
  EXPECT_EQ(*std::max_element(v.roadmap_mask_iodine_mgI_ml.begin(), v.roadmap_mask_iodine_mgI_ml.end()), 0.0F);
  EXPECT_EQ(v.pulse_tool_count, 2);
  EXPECT_FALSE(v.pulse_tool_nodes_mm[0].empty());
  EXPECT_NEAR(v.exposure.fluoro_time_s, 4.0, 1e-9);
  // The controls are in the record at the ticks of their actions.
  ASSERT_TRUE(s.recorder()->close());
  auto r_opened = RecordReader::open(path);
  ASSERT_TRUE(r_opened) << r_opened.error().message;
  auto r = std::move(*r_opened);
  TickRecord t;
  std::vector<std::pair<std::int64_t, int>> controls;
  while (r->next(t)) {
    for (std::size_t i = 0; i < t.control_count; ++i) controls.emplace_back(t.tick, t.controls[i].kind);
  }
  EXPECT_EQ(controls, (std::vector<std::pair<std::int64_t, int>>{{1000, 32}, {2500, 33}, {5000, 32}, {5100, 37}}));
  // The replay: every hash (which covers the unit from tick 1000) and figure the same.
  auto opened = Replay::open(path);
  ASSERT_TRUE(opened) << opened.error().message;
  auto& replay = *opened;
  replay->step(-1);
  const ReplayResult& rr = replay->result();
  EXPECT_TRUE(rr.matched()) << rr.error;
  EXPECT_EQ(rr.hashes_checked, 53);
  EXPECT_EQ(rr.metrics.fluoroscopy_time_s, m.fluoroscopy_time_s);
  EXPECT_EQ(rr.metrics.dose_area_product_mGy_cm2, m.dose_area_product_mGy_cm2);
  EXPECT_EQ(rr.metrics.fluoroscopy_runs, m.fluoroscopy_runs);
  EXPECT_EQ(rr.metrics.contrast_volume_ml, m.contrast_volume_ml);
  const FluoroUnit& again = *replay->session().fluoro();
  EXPECT_EQ(again.hash(0), s.fluoro()->hash(0));
  EXPECT_EQ(again.fluoroscope().image().roadmap_pulse, scope.image().roadmap_pulse);
  // The images' inputs a renderer gets are the same, number for number.
  SnapshotExchange<SceneSnapshot>& rx = replay->session().snapshots();
  (void)rx.acquire();
  const FluoroView& rv = rx.read_slot().fluoro;
  EXPECT_EQ(rv.image.pulse, v.image.pulse);
  EXPECT_EQ(rv.iodine_mgI_ml, v.iodine_mgI_ml);
  EXPECT_EQ(rv.mask_iodine_mgI_ml, v.mask_iodine_mgI_ml);
  EXPECT_EQ(rv.roadmap_iodine_mgI_ml, v.roadmap_iodine_mgI_ml);
  EXPECT_EQ(rv.roadmap_mask_iodine_mgI_ml, v.roadmap_mask_iodine_mgI_ml);
  EXPECT_EQ(rv.pulse_tool_nodes_mm[0], v.pulse_tool_nodes_mm[0]);
  EXPECT_EQ(rv.pulse_tool_nodes_mm[1], v.pulse_tool_nodes_mm[1]);
}

// The hashes of two records of the same motions, one with the pedal pressed at tick 150.
std::vector<std::uint64_t> hashes(const std::string& name, const std::string& script) {
  const std::string path = temp_path(name);
  auto scene = load("neuro.case");
  auto hand = script_hand(*scene, script);
  {
    Session s(std::move(scene), std::move(hand));
    std::string error;
    const base::Status<> recording = s.record_to(path);
    EXPECT_TRUE(recording) << recording.error().message;
    while (!s.over()) s.step_virtual(1000);
  }
  std::string error;
  auto r_opened = RecordReader::open(path);
  EXPECT_TRUE(r_opened) << r_opened.error().message;
  std::unique_ptr<RecordReader> r = r_opened ? std::move(*r_opened) : nullptr;
  std::vector<std::uint64_t> out;
  TickRecord t;
  while (r && r->next(t)) {
    if (t.state_hash) out.push_back(*t.state_hash);
  }
  return out;
}

TEST(FluoroSession, TheStateHashCoversTheFluoroscopyUnitOnceUsed) {
  const auto plain = hashes("plain.cbxrec", "0 insert_to 20 at 50\n400 end\n");
  const auto pedal = hashes("pedal.cbxrec", "0 insert_to 20 at 50\n150 fluoro on\n400 end\n");
  ASSERT_EQ(plain.size(), 4U);
  ASSERT_EQ(pedal.size(), 4U);
  EXPECT_EQ(plain[0], pedal[0]);  // tick 99: before the pedal
  EXPECT_NE(plain[1], pedal[1]);  // tick 199: the unit's state (pulses, fluoroscopy time)
  EXPECT_NE(plain[3], pedal[3]);
}

TEST(FluoroSession, ControlsFromTheFrontEndMoveTheCArmAndClearTheRoadmap) {
  auto scene = load("neuro.case");
  KeyboardInput keys;
  Session s(std::move(scene), std::make_unique<KeyboardHand>(keys, 1e-3));
  const std::string path = temp_path("carm.cbxrec");
  std::string error;
  const base::Status<> recording = s.record_to(path);
  ASSERT_TRUE(recording) << recording.error().message;
  keys.set_speeds(50.0, 0.0);
  s.step_virtual(1000);  // the catheter 50 mm in
  keys.set_speeds(0.0, 0.0);
  ASSERT_TRUE(s.post(fluoro_control::pulse_rate(30.0)));
  ASSERT_TRUE(s.post(fluoro_control::pedal(true)));
  ASSERT_TRUE(s.post(fluoro_control::inject(2.0, 4.0)));
  s.step_virtual(1000);
  ASSERT_TRUE(s.post(fluoro_control::pedal(false)));
  ASSERT_TRUE(s.post(fluoro_control::roadmap(true)));
  s.step_virtual(10);
  const FluoroUnit& u = *s.fluoro();
  EXPECT_EQ(u.fluoroscope().metrics().pulses, 30);  // 1 s at 30 pulses/s
  EXPECT_GE(u.fluoroscope().image().roadmap_pulse, 0);
  ASSERT_TRUE(s.post(fluoro_control::carm_angles(-35.0, 0.0)));   // the roadmap no longer matches
  ASSERT_TRUE(s.post(fluoro_control::carm_geometry(1100.0, 50.0, 300.0, 0.8)));
  ASSERT_TRUE(s.post(fluoro_control::carm_angles(0.0, 80.0)));    // out of range: refused
  ASSERT_TRUE(s.post(fluoro_control::pulse_rate(12.0)));           // not a rate of the unit: refused
  ASSERT_TRUE(s.post(fluoro_control::roadmap(true)));              // no run in this pose: refused
  ASSERT_TRUE(s.post(Control::make(static_cast<std::uint16_t>(ControlKind::kInject), std::vector<std::uint8_t>{6})));
  s.step_virtual(10);
  const flow::CArmPose& pose = u.fluoroscope().carm().pose();
  EXPECT_EQ(pose.lao_deg, -35.0);
  EXPECT_EQ(pose.cranial_deg, 0.0);
  EXPECT_EQ(pose.sid_mm, 1100.0);
  EXPECT_EQ(pose.table_height_mm, 50.0);
  EXPECT_EQ(pose.fov_mm, 300.0);
  EXPECT_EQ(pose.collimation, 0.8);
  EXPECT_EQ(u.fluoroscope().pulse_rate(), 30.0);
  EXPECT_EQ(u.fluoroscope().image().roadmap_pulse, -1);
  const std::vector<std::string> events = drain(s.events());
  auto has = [&events](const std::string& prefix) {
    return std::any_of(events.begin(), events.end(), [&](const std::string& e) { return e.starts_with(prefix); });
  };
  EXPECT_TRUE(has("C-arm moved: roadmap removed"));
  EXPECT_TRUE(has("C-arm: "));
  EXPECT_TRUE(has("fluoroscopy: pulse rate must be 7.5, 15 or 30"));
  EXPECT_TRUE(has("roadmap: no contrast run in this C-arm pose"));
  EXPECT_TRUE(has("fluoroscopy control kind 33: bad payload of 1 bytes"));
  s.end_run();
  s.step_virtual(1);
  ASSERT_TRUE(s.recorder()->close());
  // The refused controls are not in the record; the replay reproduces the unit.
  auto r_opened = RecordReader::open(path);
  ASSERT_TRUE(r_opened) << r_opened.error().message;
  auto r = std::move(*r_opened);
  TickRecord t;
  int controls = 0;
  while (r->next(t)) controls += static_cast<int>(t.control_count);
  EXPECT_EQ(controls, 7);
  auto opened = Replay::open(path);
  ASSERT_TRUE(opened) << opened.error().message;
  auto& replay = *opened;
  replay->step(-1);
  EXPECT_TRUE(replay->result().matched()) << replay->result().error;
  EXPECT_EQ(replay->session().fluoro()->hash(0), u.hash(0));
}

TEST(FluoroSession, AnInjectionGoesThroughTheCatheterOfTheHeldWire) {
  auto scene = load("neuro.case");  // the guidewire runs inside the catheter
  Session s(std::move(scene), script_hand(*load("neuro.case"), "0 select catheter\n0 insert_to 40 at 100\n"
                                                               "500 select guidewire\n500 insert_to 60 at 100\n"
                                                               "1200 inject 1 at 5\n1500 end\n"));
  while (!s.over()) s.step_virtual(1000);
  EXPECT_EQ(s.held_tool(), 1U);
  EXPECT_NEAR(*s.metrics().contrast_volume_ml, 1.0, 1e-9);
  const std::vector<std::string> events = drain(s.events());
  EXPECT_NE(std::find_if(events.begin(), events.end(),
                         [](const std::string& e) { return e.starts_with("inject 1.0 mL at 5.0 mL/s from the catheter's tip"); }),
            events.end());
}

// The inject control's concentration (the C-arm panel's): half the iodine for half the
// concentration, the same volume.
TEST(FluoroSession, AnInjectionCarriesItsConcentration) {
  const auto iodine_after = [](double mgI_ml) {
    KeyboardInput keys;
    Session s(load("neuro.case"), std::make_unique<KeyboardHand>(keys, 1e-3));
    keys.set_speeds(50.0, 0.0);
    s.step_virtual(1000);  // the catheter 50 mm in
    keys.set_speeds(0.0, 0.0);
    EXPECT_TRUE(s.post(fluoro_control::inject(2.0, 4.0, mgI_ml)));
    s.step_virtual(300);
    double total = 0.0;
    const flow::ContrastTransport& t = s.fluoro()->transport();
    for (std::uint32_t seg = 0; seg < t.network().model().segments.size(); ++seg) {
      for (const double c : t.cell_concentrations(seg)) total += c;
    }
    EXPECT_NEAR(*s.metrics().contrast_volume_ml, 1.2, 1e-9);  // 0.3 s at 4 mL/s so far
    return total;
  };
  const double full = iodine_after(300.0);
  EXPECT_GT(full, 0.0);
  EXPECT_NEAR(iodine_after(150.0), 0.5 * full, 1e-6 * full);
}

TEST(FluoroSession, AnInjectionNeedsACatheter) {
  auto scene = load("y_bifurcation.case");  // a guidewire only
  Session s(std::move(scene), script_hand(*load("y_bifurcation.case"), "0 insert_to 10 at 50\n100 inject 5\n300 end\n"));
  while (!s.over()) s.step_virtual(1000);
  EXPECT_EQ(s.metrics().contrast_volume_ml, 0.0);
  const std::vector<std::string> events = drain(s.events());
  EXPECT_NE(std::find(events.begin(), events.end(), "inject: the case has no catheter to inject through"), events.end());
}

TEST(FluoroSession, ControlPayloadsRoundTrip) {
  const Control i = fluoro_control::inject(6.0, 3.0);
  EXPECT_EQ(i.kind, 33);
  EXPECT_EQ(i.size, 16);
  EXPECT_EQ(i.payload[6], 0x18);  // 6.0 = 0x4018000000000000, little-endian
  EXPECT_EQ(i.payload[7], 0x40);
  const auto p = fluoro_control::read_inject(i);
  ASSERT_TRUE(p);
  EXPECT_EQ(p->volume_ml, 6.0);
  EXPECT_EQ(p->rate_ml_s, 3.0);
  EXPECT_EQ(p->concentration_mgI_ml, 300.0) << "16 bytes: the default contrast";
  // Another concentration travels as a third f64.
  const Control i350 = fluoro_control::inject(6.0, 3.0, 350.0);
  EXPECT_EQ(i350.size, 24);
  ASSERT_TRUE(fluoro_control::read_inject(i350));
  EXPECT_EQ(fluoro_control::read_inject(i350)->concentration_mgI_ml, 350.0);
  EXPECT_EQ(fluoro_control::inject(6.0, 3.0, 300.0).size, 16);
  // An action script's `inject V at R [conc C]`: the concentration travels when given.
  const auto script = tool::parse_script("0 inject 4 at 2 conc 240\n10 inject 5\n", "c.actions");
  ASSERT_TRUE(script) << script.error().message;
  const auto with_conc = fluoro_control::from_action(script->actions[0]);
  ASSERT_TRUE(with_conc);
  ASSERT_TRUE(fluoro_control::read_inject(*with_conc));
  EXPECT_EQ(fluoro_control::read_inject(*with_conc)->rate_ml_s, 2.0);
  EXPECT_EQ(fluoro_control::read_inject(*with_conc)->concentration_mgI_ml, 240.0);
  const auto without = fluoro_control::from_action(script->actions[1]);
  ASSERT_TRUE(without);
  EXPECT_EQ(without->size, 16) << "no conc: the default contrast";
  const Control r = fluoro_control::pulse_rate(7.5);
  EXPECT_EQ(r.size, 2);
  EXPECT_EQ(r.payload[0], 75);
  EXPECT_EQ(fluoro_control::read_pulse_rate(r), 7.5);
  EXPECT_EQ(fluoro_control::read_flag(fluoro_control::pedal(true)), true);
  EXPECT_FALSE(fluoro_control::read_inject(fluoro_control::pedal(true)));  // wrong size
  const auto g = fluoro_control::read_geometry(fluoro_control::carm_geometry(1000, -20, 220, 0.5));
  ASSERT_TRUE(g);
  EXPECT_EQ(g->table_height_mm, -20.0);
  EXPECT_EQ(g->collimation, 0.5);
  for (int k = 32; k <= 37; ++k) EXPECT_TRUE(known_control_kind(static_cast<std::uint16_t>(k)));
  EXPECT_FALSE(known_control_kind(38));
}

// A foot switch whose level the test sets, bouncing when asked.
class FakeFootPedal final : public device::FootPedal {
 public:
  bool level = false;
  bool broken = false;
  device::Result<bool> read() override {
    if (broken) return device::make_error(device::Errc::kIo, "gpiochip0 line 22: read failed");
    return level;
  }
};

TEST(FluoroSwitches, TheCArmKeysTurnItAStepPerPressFromWhereItIs) {
  FluoroSwitches sw;
  std::vector<Control> posted;
  auto post = [&posted](const Control& c) {
    posted.push_back(c);
    return true;
  };
  flow::CArmPose pose;
  pose.lao_deg = -35.0;
  pose.cranial_deg = 10.0;
  std::uint64_t t = 0;
  for (int i = 0; i < 10; ++i, t += 1000) sw.update({.lao = true}, t, post, &pose);  // held: one step
  ASSERT_EQ(posted.size(), 1U);
  EXPECT_EQ(posted[0].kind, static_cast<std::uint16_t>(ControlKind::kCArmAngles));
  EXPECT_DOUBLE_EQ(fluoro_control::read_angles(posted[0])->lao_deg, -30.0);
  EXPECT_DOUBLE_EQ(fluoro_control::read_angles(posted[0])->cranial_deg, 10.0);
  sw.update({}, t += 1000, post, &pose);
  sw.update({.caudal = true}, t += 1000, post, &pose);
  ASSERT_EQ(posted.size(), 2U);
  EXPECT_DOUBLE_EQ(fluoro_control::read_angles(posted[1])->cranial_deg, 5.0);
  sw.update({}, t += 1000, post, &pose);
  sw.update({.rao = true}, t += 1000, post, nullptr);  // no C-arm known: nothing
  EXPECT_EQ(posted.size(), 2U);
}

TEST(FluoroSwitches, TheKeysAndTheFootPedalPostPressesNotFrames) {
  FakeFootPedal foot;
  FluoroSwitches sw(&foot, 4.0, 2.0);
  std::vector<Control> posted;
  auto post = [&posted](const Control& c) {
    posted.push_back(c);
    return true;
  };
  std::uint64_t t = 0;
  auto frames = [&](const FluoroKeys& keys, int n) {
    for (int i = 0; i < n; ++i, t += 1000) sw.update(keys, t, post);
  };
  frames({}, 10);
  EXPECT_TRUE(posted.empty());
  frames({.pedal = true}, 10);  // held: one press
  ASSERT_EQ(posted.size(), 1U);
  EXPECT_EQ(fluoro_control::read_flag(posted[0]), true);
  frames({.pedal = true, .inject = true}, 10);  // the inject key held 10 frames: one injection
  ASSERT_EQ(posted.size(), 2U);
  EXPECT_EQ(posted[1].kind, static_cast<std::uint16_t>(ControlKind::kInject));
  EXPECT_EQ(fluoro_control::read_inject(posted[1])->volume_ml, 4.0);
  frames({}, 5);  // both released: pedal up
  ASSERT_EQ(posted.size(), 3U);
  EXPECT_EQ(fluoro_control::read_flag(posted[2]), false);
  // The foot pedal: a 2 ms bounce is not a press; 5 ms held is.
  foot.level = true;
  frames({}, 2);
  foot.level = false;
  frames({}, 3);
  EXPECT_EQ(posted.size(), 3U);
  foot.level = true;
  frames({}, 7);
  ASSERT_EQ(posted.size(), 4U);
  EXPECT_TRUE(sw.pedal_down());
  foot.broken = true;  // a read error keeps the last state and says why
  frames({}, 3);
  EXPECT_EQ(posted.size(), 4U);
  EXPECT_EQ(sw.pedal_error(), "gpiochip0 line 22: read failed");
  foot.broken = false;
  foot.level = false;
  frames({.roadmap = true}, 10);
  ASSERT_EQ(posted.size(), 6U);  // pedal up once debounced, one roadmap
  EXPECT_EQ(posted[4].kind, static_cast<std::uint16_t>(ControlKind::kRoadmap));
  EXPECT_EQ(fluoro_control::read_flag(posted[5]), false);
  EXPECT_EQ(posted[5].kind, static_cast<std::uint16_t>(ControlKind::kFluoroPedal));
  EXPECT_TRUE(sw.pedal_error().empty());
}

TEST(FluoroSwitches, FootPedalTimeIsFluoroscopyTime) {
  auto scene = load("neuro.case");
  KeyboardInput keys;
  Session s(std::move(scene), std::make_unique<KeyboardHand>(keys, 1e-3));
  FakeFootPedal foot;
  FluoroSwitches sw(&foot);
  auto post = [&s](const Control& c) { return s.post(c); };
  // A frame every 10 ms of virtual time: the foot down from 100 to 1600 ms.
  for (std::uint64_t ms = 0; ms < 2000; ms += 10) {
    foot.level = ms >= 100 && ms < 1600;
    sw.update({}, ms * 1000, post);
    s.step_virtual(10);
  }
  // Debounced 5 ms late at a 10 ms frame: pressed at the 110 ms frame, released at 1610.
  EXPECT_NEAR(*s.metrics().fluoroscopy_time_s, 1.5, 1e-9);
}

}  // namespace
}  // namespace cathbox::session
