// The stent retriever in the session (host/session/README.md, "Thrombectomy";
// docs/session/thrombectomy.md): the bundled M1 stent-retriever script run headless to
// reperfusion under balloon-guide flow arrest and replayed hash for hash.
// Sources: eTICI bands, Liebeskind et al., J NeuroIntervent Surg 2019 (the script's goal,
// eTICI >= 2b67); the embedding time, a 3-5 min dwell (World Neurosurg 2018;110:169-173);
// the retrieval force's published range, 0.24 N (straight) to 1.2 N (most tortuous) for the
// Solitaire (Front Neurol 2024;15:1486738).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <vector>
#include <cstdio>

#include "flow/centerline_locator.hpp"
#include "hand_force_trace.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "session/thrombectomy_unit.hpp"
#include "session_fixtures.hpp"
#include "stent_short_wait.hpp"

namespace cathbox::session {
namespace {

// The held tool's hand force, tick to tick while the hand holds the same tool: its largest change
// (the box slews at most 100 mN a tick: hand_force_replay_test.cpp) and where.
class HeldForceSlew : public TickObserver {
 public:
  void observe(const TickView& v) override {
    const double f = v.snapshot.tools[v.input.held].hand_force_mN;
    if (started_ && v.input.held == held_) {
      const double jump = std::abs(f - last_mN_);
      if (jump > largest_mN) largest_mN = jump, largest_ms = v.time_us / 1000, largest_tool = held_;
      ticks_over_100 += jump > 100.0 ? 1 : 0;
      if (held_ >= per_tool_mN.size()) per_tool_mN.resize(held_ + 1, 0.0), per_tool_over_100.resize(held_ + 1, 0);
      per_tool_mN[held_] = std::max(per_tool_mN[held_], jump);
      per_tool_over_100[held_] += jump > 100.0 ? 1 : 0;
    }
    started_ = true;
    held_ = v.input.held;
    last_mN_ = f;
  }
  double largest_mN = 0.0;
  std::int64_t largest_ms = 0;
  std::size_t largest_tool = 0;
  std::int64_t ticks_over_100 = 0;
  std::vector<double> per_tool_mN;  // largest change while each tool is held
  std::vector<std::int64_t> per_tool_over_100;

 private:
  bool started_ = false;
  std::size_t held_ = 0;
  double last_mN_ = 0.0;
};

// The metrics' per-tool convergence counts as they stood at a moment of the run (the
// retrieval's start), to take each tool's share over the rest of it.
class ConvergenceFrom : public TickObserver {
 public:
  explicit ConvergenceFrom(std::int64_t from_us) : from_us_(from_us) {}
  void observe(const TickView& v) override {
    if (taken_ || v.time_us < from_us_) return;
    at_from = v.metrics.convergence;
    taken_ = true;
  }
  std::vector<ToolConvergence> at_from;

 private:
  std::int64_t from_us_;
  bool taken_ = false;
};

TEST(StentRetrieverSession, M1ClotRetrievedUnderFlowArrestReperfusesAndReplays) {
  SessionCaseLoad loaded = load_session_case(fixtures::stent_short_wait_case("stent_retriever_short.case"));
  ASSERT_TRUE(loaded) << loaded.error().message;
  std::unique_ptr<Hand> script = fixtures::script_hand(*loaded.value(), fixtures::stent_short_wait_script());
  ASSERT_TRUE(script);
  const std::string path = fixtures::temp_path("session_test", "stent_retriever_m1.cbxrec");
  Metrics live;
  {
    Session s(std::move(loaded.value()), std::move(script));
    ASSERT_TRUE(s.thrombectomy());
    ASSERT_TRUE(s.record_to(path));
    const std::size_t stent = s.simulator().find_tool("stent");
    HeldForceSlew slew;
    s.add_observer(slew);
    ConvergenceFrom retrieval(static_cast<std::int64_t>(228'000 - fixtures::kStentWaitCut_ms) * 1000);  // the microcatheter into the guide
    s.add_observer(retrieval);
    double integration = 0.0;
    while (!s.over()) {
      s.step_virtual(1000);
      integration = std::max(integration, s.thrombectomy()->stent_integration(stent));
    }
    std::printf("integration reached %.3f\n", integration);
    // Measured, not bounded (issue 30 asks for the figure; issue 29 owns the slew bound).
    std::printf("hand-force slew: largest change %.1f mN/tick (%s, at %.3f s), %lld ticks change > 100 mN\n", slew.largest_mN,
                s.simulator().rod(slew.largest_tool).spec().name.c_str(), static_cast<double>(slew.largest_ms) * 1e-3,
                static_cast<long long>(slew.ticks_over_100));
    for (std::size_t t = 0; t < slew.per_tool_mN.size(); ++t) {
      std::printf("  held %-14s largest change %.1f mN/tick, %lld ticks > 100 mN\n", s.simulator().rod(t).spec().name.c_str(),
                  slew.per_tool_mN[t], static_cast<long long>(slew.per_tool_over_100[t]));
    }
    EXPECT_GT(integration, 0.9);
    // Issue 29 ("the feel"): the microcatheter drawn back over the parked stent and withdrawn
    // past its push wire changes its hand force by no more than the box's slew (100 mN a tick).
    // Its lumen friction's capstan read the push wire's clamp force, which reached 143 N (771 N
    // at one point) in the first free edges pressed against nodes held at the wall, balanced by
    // nothing on the free part: the friction stuck and dragged the microcatheter at 400 mN a
    // tick, 233 of its ticks over 100 mN, up to 1,881 mN. The capstan now reads no more than the
    // free part's external forces sum to (Rod::free_part_load_mN; convergence.md, "The M1 stent
    // retriever's jumps, by cause").
    const std::size_t microcatheter = s.simulator().find_tool("microcatheter");
    ASSERT_LT(microcatheter, slew.per_tool_over_100.size());
    EXPECT_EQ(slew.per_tool_over_100[microcatheter], 0);
    // The stent drawn back out of the M1 into the ICA terminal: each 0.5 mm node's lumen, read
    // again every 0.25 mm, stepped 2.88 -> 3.62 mm where the nearest centreline changed, and the
    // cage's radius with it: 5 ticks over 100 mN, up to 136 mN. The read now blends the two
    // lumens' radii across the junction (LumenBlend; convergence.md, "The lumen read blended").
    ASSERT_LT(stent, slew.per_tool_over_100.size());
    EXPECT_EQ(slew.per_tool_over_100[stent], 0);
    // The microwire drawn back out of the microcatheter at 100 mm/s: held at its clamp node an edge
    // behind the microcatheter's tip, each node crossing that tip changed its hand force by up to
    // 395 mN (10 ticks over 100 mN at 34.08-34.12 s). It bends from the tip of the microcatheter it
    // steers now (Simulator::hinged_at_entry; convergence.md, "Wires hinged in the catheters they
    // steer"), and that tip gives to it while it is drawn back ("A carrier steered while its tool
    // is drawn back": its end entering the tip then read -322.6 mN in a tick). The last tick over
    // the slew (-131.2 mN at 34.118 s) was the top of a sawtooth in its lumen friction, the soft
    // microcatheter kinking where the wire's core ends; the lumen's bending push is now the
    // change of the bending moment ("The lumen's bending push from the change of the moment").
    const std::size_t microwire = s.simulator().find_tool("microwire");
    ASSERT_LT(microwire, slew.per_tool_over_100.size());
    EXPECT_EQ(slew.per_tool_over_100[microwire], 0);
    live = s.metrics();
    // Issue 29: every tool's step converges on >= 99.5 % of its ticks. Over the whole run and over
    // the retrieval: the guide and the microwire (0.08 %, sub-stepped under the balloon guide:
    // docs/sim-tool/convergence.md, "Sub-stepped under a balloon guide"), the stent retriever
    // (0.28 %, 0.29 % in the retrieval) and the microcatheter (0.06 %, 0.00 % in the retrieval;
    // 1.33 / 0.66 % before, unbounded): steered by its wire while advanced and sub-stepped but
    // while the stent is being unsheathed ("The stent retriever's microcatheter sub-stepped").
    ASSERT_EQ(retrieval.at_from.size(), live.convergence.size());
    for (std::size_t t = 0; t < live.convergence.size(); ++t) {
      ToolConvergence during = live.convergence[t];
      during.solved_ticks -= retrieval.at_from[t].solved_ticks;
      during.unconverged_ticks -= retrieval.at_from[t].unconverged_ticks;
      const ToolConvergence& all = live.convergence[t];
      std::printf("  %-14s unconverged %.2f %% of %lld solved ticks; in the retrieval %.2f %% of %lld\n", all.tool.c_str(),
                  all.unconverged_pct(), static_cast<long long>(all.solved_ticks), during.unconverged_pct(),
                  static_cast<long long>(during.solved_ticks));
      EXPECT_LE(all.unconverged_pct(), test::kUnconvergedMax_pct) << all.tool;
      EXPECT_LE(during.unconverged_pct(), test::kUnconvergedMax_pct) << all.tool << " in the retrieval";
    }
  }
  ASSERT_TRUE(live.thrombectomy);
  const ThrombectomyFigures& t = *live.thrombectomy;
  std::printf("M1 stent retriever: %d pass(es), eTICI %s (%.0f %%), %d emboli, retrieval force %.3f N, reperfused at %.1f s\n", t.passes,
              std::string(flow::etici_label(t.etici_final)).c_str(), t.reperfused_pct_final, t.emboli, t.retrieval_force_peak_N,
              static_cast<double>(t.time_to_reperfusion_us) * 1e-6);
  EXPECT_EQ(t.passes, 1);
  EXPECT_EQ(t.stent_passes, 1);
  EXPECT_TRUE(flow::at_least(t.etici_final, flow::Etici::k2b67));
  EXPECT_EQ(t.emboli, 0);
  // In the published range (Front Neurol 2024): not below the Solitaire's straight-model figure
  // (0.24 +- 0.01 N; the pull also drags the clot), not above its most tortuous one (1.2 +- 0.08
  // N) + 2 SD: the case's M1 into the carotid terminus is a tortuous path.
  EXPECT_GT(t.retrieval_force_peak_N, 0.24 - 3.0 * 0.01);
  EXPECT_LT(t.retrieval_force_peak_N, 1.2 + 2.0 * 0.08);
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  ASSERT_TRUE(r.metrics.thrombectomy);
  EXPECT_EQ(*r.metrics.thrombectomy, t);
}

// The careless contrast (issue 30: no flow arrest, fast retrieval): the same deployment and
// embedding, no balloon guide, the microcatheter left where it unsheathed the stent and the stent
// pulled at 20 mm/s straight into it. The stent holds the clot (grip > the head's hold), but the
// microcatheter's tip strips it off the struts into the flow (whole: the flow's shear is far
// below what tears a clot, sim/flow clot_fracture.hpp), and the flow carries it back into the
// M1, where it lodges tens of ms later: an embolus, eTICI 0, against the careful run's eTICI 3
// in one pass without emboli (thrombectomy_unit.hpp, "Stent retrievers").
TEST(StentRetrieverSession, CarelessRunWithoutFlowArrestLosesTheClot) {
  SessionCaseLoad loaded = load_session_case(fixtures::stent_short_wait_case("stent_retriever_short_careless.case"));
  ASSERT_TRUE(loaded) << loaded.error().message;
  std::unique_ptr<Hand> script =
      fixtures::script_hand(*loaded.value(),
                            fixtures::stent_short_wait_script("neuro_thrombectomy_m1_stentretriever_careless.actions"));
  ASSERT_TRUE(script);
  Session s(std::move(loaded.value()), std::move(script));
  ASSERT_TRUE(s.thrombectomy());
  std::string stent_lines;
  while (!s.over()) {
    s.step_virtual(1000);
    for (LogEvent e; s.events().pop(e);) {
      const std::string line = e.text.data();
      if (line.find("stent") != std::string::npos || line.find("pass ") != std::string::npos || line.find("embol") != std::string::npos ||
          line.find("fragment") != std::string::npos) {
        stent_lines += line + "\n";
      }
    }
  }
  std::printf("%s", stent_lines.c_str());
  EXPECT_NE(stent_lines.find("stent retriever across the clot"), std::string::npos);
  EXPECT_NE(stent_lines.find("the clot comes with the stent"), std::string::npos);
  EXPECT_NE(stent_lines.find("pass 1: re-sheathed in the microcatheter, the clot is stripped off into the flow"), std::string::npos);
  EXPECT_NE(stent_lines.find("embolus lodged in the left_middle_cerebral"), std::string::npos);
  const Metrics m = s.metrics();
  ASSERT_TRUE(m.thrombectomy);
  const ThrombectomyFigures& t = *m.thrombectomy;
  std::printf("careless M1 stent retriever: %d pass(es), eTICI %s (%.0f %%), %d emboli (%d new territory), retrieval force %.3f N\n",
              t.passes, std::string(flow::etici_label(t.etici_final)).c_str(), t.reperfused_pct_final, t.emboli,
              t.emboli_new_territory, t.retrieval_force_peak_N);
  EXPECT_EQ(t.passes, 1);
  EXPECT_EQ(t.stent_passes, 1);
  EXPECT_EQ(t.etici_final, flow::Etici::k0);
  EXPECT_FALSE(flow::at_least(t.etici_final, flow::Etici::k2b50));
  EXPECT_FALSE(t.first_pass_effect);
  EXPECT_EQ(t.time_to_reperfusion_us, -1) << "not reperfused";
  EXPECT_EQ(t.emboli, 1);
  ASSERT_EQ(t.emboli_lodged.size(), 1u);
  EXPECT_EQ(t.emboli_lodged[0].rfind("left_middle_cerebral", 0), 0u) << t.emboli_lodged[0];
  EXPECT_EQ(t.emboli_new_territory, 0) << "into the MCA, the target territory";
  // Stripped at the microcatheter's tip after a few mm: a lighter peak pull than the careful
  // run's, which drags the clot back to the guide.
  EXPECT_GT(t.retrieval_force_peak_N, 0.0);
  EXPECT_LT(t.retrieval_force_peak_N, 0.3);
}

}  // namespace
}  // namespace cathbox::session
