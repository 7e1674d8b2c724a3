// Thrombectomy in the session (host/session/README.md, "Thrombectomy"): the bundled carotid-T
// aspiration under balloon-guide flow arrest run as a session to reperfusion and replayed; the
// thrombectomy unit's passes on the M1 case with the catheter's tip placed by hand (ingested:
// eTICI 3 and the territory's flow back to baseline; lost: the clot stays and a fragment
// embolizes, none under flow arrest).
// Sources: eTICI bands, Liebeskind et al., J NeuroIntervent Surg 2019; the vacuum (pump
// -25.6 inHg, syringe -27.0 inHg), Froehler, J NeuroIntervent Surg 2017; "within 5 % of
// baseline after complete removal": issue 30's validation.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <map>
#include <fstream>
#include <sstream>

#include <glm/geometric.hpp>

#include "flow/centerline_locator.hpp"
#include "session/action_script_hand.hpp"
#include "session/event_log.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "session/thrombectomy_unit.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

const std::string kCases = std::string(CATHBOX_SOURCE_DIR) + "/cases/";

TEST(ThrombectomySession, CarotidTAspirationUnderFlowArrestReperfusesAndReplays) {
  SessionCaseLoad loaded = load_session_case(kCases + "neuro_thrombectomy_ica_t.case");
  ASSERT_TRUE(loaded) << loaded.error().message;
  auto script = ActionScriptHand::load(kCases + "neuro_thrombectomy_ica_t.actions", *loaded.value());
  ASSERT_TRUE(script) << (script ? "" : script.error().message);
  auto hand = std::move(*script);
  const std::string path = fixtures::temp_path("session_test", "thrombectomy_ica_t.cbxrec");
  Metrics live;
  {
    Session s(std::move(loaded.value()), std::move(hand));
    ASSERT_TRUE(s.thrombectomy());
    const base::Status<> recording = s.record_to(path);
    ASSERT_TRUE(recording) << recording.error().message;
    while (!s.over()) s.step_virtual(1000);
    EXPECT_EQ(s.end_reason(), record::EndReason::kHandFinished);
    live = s.metrics();
    // The control angiogram after the pass: the contrast from the guide fills the left MCA's
    // M2s again (the fluoroscopy follows the re-solved network), as in the open network
    // (sim/flow Occlusion.ContrastStopsAtTheClot: 116 mgI/mL in the M2 at 1.5 s).
    ASSERT_TRUE(s.fluoro());
    const flow::ContrastTransport& t = s.fluoro()->transport();
    double m2_mgI_ml = 0.0;
    for (std::uint32_t k = 0; k < t.network().model().segments.size(); ++k) {
      if (t.network().model().segments[k].name.rfind("left_middle_cerebral_m2", 0) == 0) m2_mgI_ml = std::max(m2_mgI_ml, t.max_concentration(k));
    }
    std::printf("control run: left M2 %.1f mgI/mL\n", m2_mgI_ml);
    EXPECT_GT(m2_mgI_ml, 30.0);
  }
  ASSERT_TRUE(live.thrombectomy);
  const ThrombectomyFigures& t = *live.thrombectomy;
  std::printf("carotid-T: %d pass(es), eTICI %s, %d emboli, reperfused at %.3f s\n", t.passes,
              std::string(flow::etici_label(t.etici_final)).c_str(), t.emboli, static_cast<double>(t.time_to_reperfusion_us) * 1e-6);
  EXPECT_EQ(t.passes, 1);
  EXPECT_EQ(t.etici_after_pass[0], flow::Etici::k3);
  EXPECT_EQ(t.etici_final, flow::Etici::k3);
  EXPECT_TRUE(t.first_pass_effect);
  EXPECT_EQ(t.emboli, 0);
  // The pass ends 10 mm into the withdrawal that starts at 11 s (0.1 mm at 2 mm/s, then 10 mm/s):
  // 11.05 + 9.9 / 10 = 12.04 s.
  constexpr double kReperfused_s = 11.05 + 9.9 / 10.0;
  EXPECT_NEAR(static_cast<double>(t.time_to_reperfusion_us) * 1e-6, kReperfused_s, 0.01);
  // The balloon guide (not an angioplasty balloon): inflated once at 9 s, deflated at 14.5 s.
  EXPECT_EQ(t.balloon_guide_inflations, 1);
  EXPECT_NEAR(t.flow_arrest_s, 5.5, 0.002);
  EXPECT_EQ(live.balloon_inflations.value_or(0), 0);  // the angioplasty balloon's count: not the guide's
  EXPECT_NE(MetricsCollector::format(live).find("flow arrest           5.50 s\n"), std::string::npos) << MetricsCollector::format(live);
  // The server's named metrics: eTICI as its ordinal (3 = 6), every name one metric_names() lists.
  const std::vector<std::string> names = metric_names();
  std::map<std::string, double> named;
  for (const NamedMetric& n : named_metrics(live)) {
    named[n.name] = n.value;
    if (n.name.rfind("unconverged_pct.", 0) != 0) {
      EXPECT_NE(std::find(names.begin(), names.end(), n.name), names.end()) << n.name;
    }
  }
  EXPECT_EQ(named["thrombectomy_passes"], 1.0);
  EXPECT_EQ(named["etici_pass_1"], 6.0);
  EXPECT_EQ(named["balloon_guide_inflations"], 1.0);
  EXPECT_NEAR(named["flow_arrest_s"], 5.5, 0.002);
  EXPECT_EQ(named["etici_final"], 6.0);
  EXPECT_EQ(named["first_pass_effect"], 1.0);
  EXPECT_EQ(named["emboli"], 0.0);
  EXPECT_NEAR(named["time_to_reperfusion_s"], kReperfused_s, 0.01);
  // Aspiration on / off and the balloon guide inflated / deflated: four controls in the record.
  auto opened = RecordReader::open(path);
  ASSERT_TRUE(opened) << opened.error().message;
  int aspiration = 0;
  int guide = 0;
  TickRecord tick;
  while ((*opened)->next(tick)) {
    for (std::size_t i = 0; i < tick.control_count; ++i) {
      aspiration += tick.controls[i].kind == static_cast<std::uint16_t>(ControlKind::kAspiration) ? 1 : 0;
      guide += tick.controls[i].kind == static_cast<std::uint16_t>(ControlKind::kBalloonGuide) ? 1 : 0;
    }
  }
  EXPECT_EQ(aspiration, 2);
  EXPECT_EQ(guide, 2);
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  EXPECT_GT(r.hashes_checked, 100);
  ASSERT_TRUE(r.metrics.thrombectomy);
  EXPECT_EQ(*r.metrics.thrombectomy, t);
}

// The M1 case (or a variant of its text) loaded, and a unit on its occluded network.
struct M1 {
  std::unique_ptr<SessionCase> scene;
  EventLog events;
  std::unique_ptr<ThrombectomyUnit> unit;
  tool::Snapshot snap;
  std::uint32_t m1 = 0;
  std::uint32_t ica_terminal = 0;
  std::uint32_t ica = 0;
};

std::uint32_t index_of(const vessel::VesselModel& m, std::int32_t id) { return static_cast<std::uint32_t>(*m.index_of(id)); }

void load_m1(M1& out, const std::vector<std::pair<std::string, std::string>>& replace = {}) {
  std::ifstream in(kCases + "neuro_thrombectomy_m1.case");
  std::stringstream buf;
  buf << in.rdbuf();
  std::string text = buf.str();
  text.replace(text.find("vessel neuro.hclm"), 17, "vessel " + kCases + "neuro.hclm");
  for (const auto& [from, to] : replace) {
    const std::size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from;
    text.replace(at, from.size(), to);
  }
  // Each test its own file: ctest runs these tests side by side, and one truncating the file
  // another is reading handed it an empty case ("no vessel").
  const std::string path = fixtures::temp_path(
      "session_test", std::string("m1_variant_") + ::testing::UnitTest::GetInstance()->current_test_info()->name() + ".case");
  std::ofstream(path) << text;
  SessionCaseLoad loaded = load_session_case(path);
  ASSERT_TRUE(loaded) << loaded.error().message;
  out.scene = std::move(loaded.value());
  std::string why;
  out.unit = ThrombectomyUnit::make(*out.scene->flow, out.scene->spec, out.events, why);
  ASSERT_TRUE(out.unit) << why;
  out.snap.tools.resize(out.scene->spec.tools.size());
  const vessel::VesselModel& model = out.scene->flow->model();
  out.m1 = index_of(model, 22);
  out.ica_terminal = index_of(model, 21);
  out.ica = index_of(model, 20);
}

double left_mca_ml_min(const flow::FlowNetwork& net) {
  double q = 0.0;
  for (const flow::Terminal& t : net.terminals()) {
    if (net.model().segments[t.segment].name.rfind("left_middle_cerebral_m2", 0) == 0) q += t.flow_ml_min;
  }
  return q;
}

// The newest line of the log (the others dropped).
std::string last_event(EventLog& log) {
  std::string last;
  for (LogEvent e; log.pop(e);) last = e.text.data();
  return last;
}

constexpr std::size_t kGuide = 0;
constexpr std::size_t kAspirationCatheter = 1;
constexpr std::size_t kMicrowire = 3;

// The aspiration catheter's tip at `point`, inserted `insertion_mm`; one tick.
void place(M1& c, const glm::dvec3& point, double insertion_mm, std::int64_t time_us) {
  c.snap.tools[kAspirationCatheter].tip.position_mm = point;
  c.snap.tools[kAspirationCatheter].insertion_mm = insertion_mm;
  c.unit->tick(time_us, c.snap);
}

TEST(ThrombectomyUnit, AnM1ClotIngestedOnTheFirstPassReperfusesTheTerritory) {
  SessionCaseLoad open = load_session_case(kCases + "neuro.case");
  ASSERT_TRUE(open) << open.error().message;
  const double baseline = left_mca_ml_min(*open.value()->flow);
  M1 c;
  load_m1(c);
  ASSERT_TRUE(c.unit);
  EXPECT_EQ(c.unit->figures().etici_final, flow::Etici::k0);
  EXPECT_EQ(c.unit->figures().reperfused_pct_final, 0.0);
  const flow::CenterlineLocator loc(c.scene->flow->model());
  const glm::dvec3 face = loc.point_at(c.m1, 2.0);  // the clot starts 2 mm into the M1
  // The tip at the face without aspiration: nothing; aspiration on a tool without a vacuum
  // source or a balloon guide on one without a balloon: refused.
  place(c, face, 130.0, 1000);
  EXPECT_FALSE(c.unit->engaged());
  EXPECT_FALSE(c.unit->set_aspiration(kMicrowire, true, 1000));
  EXPECT_FALSE(c.unit->set_balloon_guide(kMicrowire, true, 1000));
  ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, true, 2000));
  EXPECT_FALSE(c.unit->set_aspiration(kAspirationCatheter, true, 2000)) << "already on";
  place(c, face, 130.0, 3000);
  EXPECT_TRUE(c.unit->engaged());
  EXPECT_EQ(c.unit->aspiration_grip_mN(kAspirationCatheter), 0.0) << "an ingested clot slides in: no pull on the tip";
  // Withdrawn 9 mm: not yet a pass; 10 mm: the pass.
  place(c, loc.point_at(c.ica_terminal, 5.0), 121.0, 4000);
  EXPECT_EQ(c.unit->figures().passes, 0);
  place(c, loc.point_at(c.ica_terminal, 4.0), 120.0, 5000);
  const ThrombectomyFigures& f = c.unit->figures();
  ASSERT_EQ(f.passes, 1);
  // Red-cell-rich (60 % red cells), 0.068" catheter on the pump: ingested (sim/flow's
  // Aspiration tests), the M1 open: eTICI 3, the first-pass effect, the left MCA's flow back
  // within 5 % of baseline.
  EXPECT_TRUE(c.unit->clots().empty());
  EXPECT_EQ(f.etici_after_pass[0], flow::Etici::k3);
  EXPECT_TRUE(f.first_pass_effect);
  EXPECT_EQ(f.time_to_reperfusion_us, 5000);
  EXPECT_EQ(f.emboli, 0);
  // The tip open again with the vacuum on: the catheter draws blood from the network at its
  // node (sim/flow "Aspiration sink"), which the MCA misses until aspiration goes off.
  ASSERT_EQ(c.scene->flow->sinks().size(), 1u);
  const double drawn = c.scene->flow->sink_flow_ml_min(0);
  std::printf("the open 0.068\" tip draws %.1f mL/min; left MCA %.1f mL/min (open %.1f)\n", drawn, left_mca_ml_min(*c.scene->flow), baseline);
  EXPECT_GT(drawn, 100.0);
  EXPECT_LT(left_mca_ml_min(*c.scene->flow), baseline - 0.05 * baseline);
  ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, false, 6000));
  EXPECT_TRUE(c.scene->flow->sinks().empty());
  EXPECT_NEAR(left_mca_ml_min(*c.scene->flow), baseline, 0.05 * baseline);
}

// A fibrin-rich clot on the 0.068" catheter corks its tip (sim/flow's
// Aspiration.M1ClotsAreIngestedCorkedOrLost): the catheter drags it, and its tip takes what holds
// the clot in place (its static wall friction under the wedge strain and the head across it),
// below the vacuum's pull; the pass takes it out and the grip ends.
TEST(ThrombectomyUnit, ACorkedClotPullsOnTheAspirationCathetersTipWithWhatHoldsIt) {
  M1 c;
  load_m1(c, {{"red=60 fibrin=30", "red=15 fibrin=75"}});
  ASSERT_TRUE(c.unit);
  const flow::CenterlineLocator loc(c.scene->flow->model());
  ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, true, 0));
  place(c, loc.point_at(c.m1, 2.0), 130.0, 1000);
  ASSERT_TRUE(c.unit->engaged());
  const double vacuum_mN = 1000.0 * flow::aspiration_force_N(flow::VacuumSource::kPump, 1.73);
  const double grip_mN = c.unit->aspiration_grip_mN(kAspirationCatheter);
  const flow::AspirationClot clot{2.0 * loc.radius_at(c.m1, 2.0), c.unit->clots()[0].length_mm, c.unit->clots()[0].composition};
  const flow::SegmentFlow& m1 = c.scene->flow->segments()[c.m1];
  const double head_Pa = c.scene->flow->node_pressure_Pa(m1.start_node) - c.scene->flow->node_pressure_Pa(m1.end_node);
  std::printf("corked: the tip holds %.1f mN of the vacuum's %.1f mN\n", grip_mN, vacuum_mN);
  EXPECT_NEAR(grip_mN, 1000.0 * flow::clot_hold_force_N(clot, head_Pa), 1e-6);
  EXPECT_GT(grip_mN, 0.0);
  EXPECT_LT(grip_mN, vacuum_mN);
  place(c, loc.point_at(c.ica_terminal, 2.0), 118.0, 2000);
  ASSERT_EQ(c.unit->figures().passes, 1);
  EXPECT_TRUE(c.unit->clots().empty());
  EXPECT_EQ(c.unit->aspiration_grip_mN(kAspirationCatheter), 0.0);
}

// Ticks the unit every 1 ms from `from_us` until no embolus is in transit (at most 1 s); the
// time of the last tick.
std::int64_t carry_emboli(M1& c, std::int64_t from_us) {
  std::int64_t t = from_us;
  while (c.unit->emboli_in_transit() > 0 && t < from_us + 1000000) c.unit->tick(t += 1000, c.snap);
  return t;
}

TEST(ThrombectomyUnit, ALostFibrinRichClotStaysAndEmbolizesButNotUnderFlowArrest) {
  // A 3MAX-sized lumen (0.035") against a fibrin-rich clot: lost against the flowing pressure
  // head (sim/flow's Aspiration.M1ClotsAreIngestedCorkedOrLost).
  M1 c;
  load_m1(c, {{"inner_diameter 1.73", "inner_diameter 0.89"}, {"red=60 fibrin=30", "red=15 fibrin=75"}});
  ASSERT_TRUE(c.unit);
  const flow::CenterlineLocator loc(c.scene->flow->model());
  const glm::dvec3 face = loc.point_at(c.m1, 2.0);
  ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, true, 0));
  place(c, face, 130.0, 1000);
  ASSERT_TRUE(c.unit->engaged());
  // Aspiration off while engaged lets the clot go: no pass.
  ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, false, 2000));
  EXPECT_FALSE(c.unit->engaged());
  place(c, loc.point_at(c.ica_terminal, 2.0), 118.0, 3000);
  EXPECT_EQ(c.unit->figures().passes, 0);
  // Pass 1, no flow arrest: lost; the fragment stripped off at the tip (in the ICA terminus)
  // follows the flow the occluded M1 leaves: the anterior cerebral artery, a new territory.
  ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, true, 4000));
  place(c, face, 130.0, 5000);
  // Lost: the vacuum holds the clot on the tip with |p| x area (Froehler 2017) until the pull
  // exceeds it; that is what the tip grips with.
  EXPECT_NEAR(c.unit->aspiration_grip_mN(kAspirationCatheter), 1000.0 * flow::aspiration_force_N(flow::VacuumSource::kPump, 0.89), 1e-9);
  EXPECT_EQ(c.unit->aspiration_grip_mN(kGuide), 0.0);
  place(c, loc.point_at(c.ica_terminal, 2.0), 118.0, 6000);
  const ThrombectomyFigures& f = c.unit->figures();
  ASSERT_EQ(f.passes, 1);
  EXPECT_EQ(f.etici_after_pass[0], flow::Etici::k0);
  EXPECT_FALSE(f.first_pass_effect);
  // The fragment travels with the flow (tens of ms at these velocities): not an embolus until it
  // lodges.
  EXPECT_EQ(c.unit->emboli_in_transit(), 1u);
  EXPECT_EQ(f.emboli, 0);
  const std::int64_t lodged_us = carry_emboli(c, 6000);
  std::printf("pass 1: the fragment lodges %.0f ms after the pass\n", 1e-3 * static_cast<double>(lodged_us - 6000));
  EXPECT_EQ(c.unit->emboli_in_transit(), 0u);
  EXPECT_GT(lodged_us, 7000);
  EXPECT_LT(lodged_us, 6000 + 500000);
  EXPECT_EQ(f.emboli, 1);
  ASSERT_EQ(f.emboli_lodged.size(), 1u);
  std::printf("pass 1: embolus lodged in %s (%d to new territories)\n", f.emboli_lodged[0].c_str(), f.emboli_new_territory);
  EXPECT_EQ(f.emboli_new_territory, 1);
  EXPECT_EQ(f.emboli_lodged[0].rfind("left_anterior_cerebral", 0), 0u) << f.emboli_lodged[0];
  EXPECT_EQ(c.unit->clots().size(), 2u) << "the clot stays, the embolus lodged";
  // Pass 2 under the balloon guide's flow arrest (the guide in the cervical ICA): still lost
  // (the circle of Willis keeps the head across the M1 clot), but no flow carries the fragment:
  // no new embolus.
  const std::int64_t t0 = lodged_us;
  c.snap.tools[kGuide].tip.position_mm = loc.point_at(c.ica, 10.0);
  c.unit->tick(t0 + 500, c.snap);
  ASSERT_TRUE(c.unit->set_balloon_guide(kGuide, true, t0 + 1000));
  EXPECT_EQ(last_event(c.events), "balloon guide inflated in the left_internal_carotid: flow arrest");
  EXPECT_TRUE(c.unit->arrested());
  EXPECT_FALSE(c.unit->set_balloon_guide(kGuide, true, t0 + 1000)) << "already inflated";
  place(c, face, 130.0, t0 + 2000);
  place(c, loc.point_at(c.ica_terminal, 2.0), 118.0, t0 + 3000);
  ASSERT_EQ(f.passes, 2);
  // Not a rule: the catheter's open tip is the only way out of the arrested column at its node.
  EXPECT_EQ(last_event(c.events).rfind("the aspiration catheter draws the fragment in", 0), 0u) << last_event(c.events);
  EXPECT_EQ(f.emboli, 1);
  EXPECT_EQ(f.etici_after_pass[1], flow::Etici::k0);
  EXPECT_EQ(f.time_to_reperfusion_us, -1);
  // The arrest's figures: one inflation (the refused second not counted), its time running up to
  // the last tick (3 ms after the fragment lodged) while inflated, closed at the deflation (4 ms).
  EXPECT_EQ(f.balloon_guide_inflations, 1);
  EXPECT_NEAR(f.flow_arrest_s, 0.002, 1e-9);
  ASSERT_TRUE(c.unit->set_balloon_guide(kGuide, false, t0 + 4000));
  EXPECT_FALSE(c.unit->arrested());
  EXPECT_NEAR(f.flow_arrest_s, 0.003, 1e-9);
  c.unit->tick(t0 + 5000, c.snap);
  EXPECT_NEAR(f.flow_arrest_s, 0.003, 1e-9) << "deflated: the arrest time stays";
  EXPECT_EQ(f.balloon_guide_inflations, 1);
}

// Pass 1 of the lost fibrin-rich clot (above) without arrest, up to `t_us`: the fragment
// stripped off at the tip released into the flow.
void lose_a_fragment(M1& c, std::int64_t t_us) {
  load_m1(c, {{"inner_diameter 1.73", "inner_diameter 0.89"}, {"red=60 fibrin=30", "red=15 fibrin=75"}});
  ASSERT_TRUE(c.unit);
  const flow::CenterlineLocator loc(c.scene->flow->model());
  ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, true, t_us - 2000));
  place(c, loc.point_at(c.m1, 2.0), 130.0, t_us - 1000);
  place(c, loc.point_at(c.ica_terminal, 2.0), 118.0, t_us);
  ASSERT_EQ(c.unit->figures().passes, 1);
  ASSERT_EQ(c.unit->emboli_in_transit(), 1u);
}

TEST(ThrombectomyUnit, AFragmentStillInTransitWhenTheRunEndsIsCountedWhereTheFlowWouldLodgeIt) {
  // Two identical runs: one ends 1 ms after the pass, the fragment on its way; the other carries
  // it on in virtual time until it lodges. The first counts what the second sees happen.
  M1 ended;
  M1 carried;
  lose_a_fragment(ended, 6000);
  lose_a_fragment(carried, 6000);
  ended.unit->tick(7000, ended.snap);
  ASSERT_EQ(ended.unit->emboli_in_transit(), 1u);
  // Drawn in the 3D view as it travels: its diameter (the 0.035" lumen's 0.89 mm), its axis on
  // its segment's centreline ending at its leading point.
  const ClotView drawn = ended.unit->embolus_view(0);
  EXPECT_EQ(drawn.state, ClotState::kInTransit);
  EXPECT_NEAR(drawn.radius_mm, 0.445, 1e-6);
  const flow::CenterlineLocator loc(ended.scene->flow->model());
  for (const glm::vec3& p : drawn.axis_mm) EXPECT_LT(loc.nearest(glm::dvec3(p)).distance_mm, 1e-3);
  EXPECT_GT(glm::length(drawn.end_mm - drawn.start_mm), 0.0F);
  const std::vector<flow::Terminal> before = ended.scene->flow->terminals();
  ended.unit->finish(7000);
  (void)carry_emboli(carried, 6000);
  const ThrombectomyFigures& e = ended.unit->figures();
  const ThrombectomyFigures& c = carried.unit->figures();
  ASSERT_EQ(c.emboli_lodged.size(), 1u);
  ASSERT_EQ(e.emboli_in_transit.size(), 1u);
  const EmbolusInTransit& t = e.emboli_in_transit[0];
  std::printf("in transit in the %s at %.1f mm: would lodge in the %s%s\n", t.at.c_str(), t.at_mm, t.would_lodge.c_str(),
              t.new_territory ? " (ENT)" : "");
  EXPECT_EQ(t.would_lodge, c.emboli_lodged[0]);
  EXPECT_TRUE(t.new_territory) << "the left A2: outside the MCA territory";
  EXPECT_EQ(e.emboli, 1);
  EXPECT_EQ(e.emboli_new_territory, c.emboli_new_territory);
  EXPECT_TRUE(e.emboli_lodged.empty()) << "not lodged: counted, not listed as lodged";
  // Where it was: 1 ms after leaving the tip in the ICA terminus, still in the carotid's branches.
  EXPECT_EQ(t.at.rfind("left_", 0), 0u) << t.at;
  EXPECT_GE(t.at_mm, 0.0);
  // The grade is the final angiogram's: the fragment not lodged yet, and the network as it was.
  EXPECT_EQ(e.etici_final, flow::Etici::k0);
  EXPECT_EQ(ended.unit->clots().size(), 1u);
  const std::vector<flow::Terminal> after = ended.scene->flow->terminals();
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t k = 0; k < after.size(); ++k) EXPECT_NEAR(after[k].flow_ml_min, before[k].flow_ml_min, 1e-9) << k;
  // Once per run.
  ended.unit->finish(8000);
  EXPECT_EQ(ended.unit->figures().emboli, 1);
  // The named metrics count it.
  Metrics m;
  m.thrombectomy = e;
  double named = -1.0;
  for (const NamedMetric& n : named_metrics(m)) named = n.name == "emboli_in_transit" ? n.value : named;
  EXPECT_EQ(named, 1.0);
  EXPECT_NE(MetricsCollector::format(m).find("would lodge in the " + t.would_lodge), std::string::npos) << MetricsCollector::format(m);
}

// Two clots, the first in the list taken out, so ids and places in the list differ: a short
// red-cell-rich clot in the right M1 (segment 15) ingested or corked by pass 1; then pass 2 loses
// the fibrin-rich left M1 clot and its fragment is on its way when the run ends. finish() lodges
// the fragment as a clot of its own for its figures and takes that one out again by its id: the
// left M1 clot stays, alone, and the network is as it was (a mix-up of ids and places would
// erase the left M1 clot and leave the embolus in the network).
TEST(ThrombectomyUnit, FinishTakesOutTheClotItLodgedNotOneThatRemains) {
  const auto run_to_a_lost_fragment = [](M1& c) {
    load_m1(c, {{"inner_diameter 1.73", "inner_diameter 0.89"},
                {"clot 22 2 13 red=60 fibrin=30", "clot 15 2 2 red=60 fibrin=30\nclot 22 2 13 red=15 fibrin=75"}});
    ASSERT_TRUE(c.unit);
    ASSERT_EQ(c.unit->clots().size(), 2u);
    const std::uint32_t right_m1 = index_of(c.scene->flow->model(), 15);
    ASSERT_EQ(c.unit->clots()[0].segment, right_m1);
    const flow::CenterlineLocator loc(c.scene->flow->model());
    ASSERT_TRUE(c.unit->set_aspiration(kAspirationCatheter, true, 0));
    place(c, loc.point_at(right_m1, 2.0), 130.0, 1000);
    ASSERT_TRUE(c.unit->engaged());
    place(c, loc.point_at(right_m1, 0.5), 118.0, 2000);
    ASSERT_EQ(c.unit->figures().passes, 1);
    ASSERT_EQ(c.unit->clots().size(), 1u) << "pass 1 takes the right M1 clot out";
    ASSERT_EQ(c.unit->clots()[0].segment, c.m1);
    place(c, loc.point_at(c.m1, 2.0), 130.0, 3000);
    ASSERT_TRUE(c.unit->engaged());
    place(c, loc.point_at(c.ica_terminal, 2.0), 118.0, 4000);
    ASSERT_EQ(c.unit->figures().passes, 2);
    ASSERT_EQ(c.unit->clots().size(), 1u) << "lost: the left M1 clot stays";
    ASSERT_EQ(c.unit->emboli_in_transit(), 1u);
  };
  M1 ended;
  M1 carried;
  run_to_a_lost_fragment(ended);
  run_to_a_lost_fragment(carried);
  if (HasFatalFailure()) return;
  ended.unit->tick(5000, ended.snap);
  ASSERT_EQ(ended.unit->emboli_in_transit(), 1u);
  const flow::Clot before_clot = ended.unit->clots()[0];
  const std::vector<flow::Terminal> before = ended.scene->flow->terminals();
  ended.unit->finish(5000);
  (void)carry_emboli(carried, 4000);
  ASSERT_EQ(carried.unit->figures().emboli_lodged.size(), 1u);
  ASSERT_EQ(ended.unit->figures().emboli_in_transit.size(), 1u);
  EXPECT_EQ(ended.unit->figures().emboli_in_transit[0].would_lodge, carried.unit->figures().emboli_lodged[0]);
  // The clot that remains is the left M1's, as it was; the network occluded by it alone again.
  ASSERT_EQ(ended.unit->clots().size(), 1u);
  EXPECT_EQ(ended.unit->clots()[0].segment, before_clot.segment);
  EXPECT_EQ(ended.unit->clots()[0].arc_start_mm, before_clot.arc_start_mm);
  EXPECT_EQ(ended.unit->clots()[0].length_mm, before_clot.length_mm);
  const std::vector<flow::Terminal> after = ended.scene->flow->terminals();
  ASSERT_EQ(after.size(), before.size());
  for (std::size_t k = 0; k < after.size(); ++k) EXPECT_NEAR(after[k].flow_ml_min, before[k].flow_ml_min, 1e-9) << k;
  // A new pass on the remaining clot still engages it by its id (the vacuum holds the left M1's).
  const flow::CenterlineLocator loc(ended.scene->flow->model());
  place(ended, loc.point_at(ended.m1, 2.0), 130.0, 6000);
  EXPECT_TRUE(ended.unit->engaged());
  EXPECT_GT(ended.unit->aspiration_grip_mN(kAspirationCatheter), 0.0) << "the fibrin-rich clot on the 0.035\" lumen pulls";
}

}  // namespace
}  // namespace cathbox::session
