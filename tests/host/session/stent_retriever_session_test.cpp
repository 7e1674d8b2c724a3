// The stent retriever in the session (host/session/README.md, "Thrombectomy";
// docs/session/thrombectomy.md): the bundled M1 stent-retriever script run headless to
// reperfusion under balloon-guide flow arrest and replayed hash for hash.
// Sources: eTICI bands, Liebeskind et al., J NeuroIntervent Surg 2019 (the script's goal,
// eTICI >= 2b67); the embedding time, a 3-5 min dwell (World Neurosurg 2018;110:169-173);
// the retrieval force's published range 0.24-1.6 N (Front Neurol 2024;15:1486738).
#include <gtest/gtest.h>

#include <cstdio>

#include "flow/centerline_locator.hpp"
#include "session/action_script_hand.hpp"
#include "session/replay.hpp"
#include "session/session.hpp"
#include "session/thrombectomy_unit.hpp"
#include "session_fixtures.hpp"

namespace cathbox::session {
namespace {

const std::string kCases = std::string(CATHBOX_SOURCE_DIR) + "/cases/";

TEST(StentRetrieverSession, M1ClotRetrievedUnderFlowArrestReperfusesAndReplays) {
  SessionCaseLoad loaded = load_session_case(kCases + "neuro_thrombectomy_m1_stentretriever.case");
  ASSERT_TRUE(loaded.value) << loaded.error;
  auto script = ActionScriptHand::load(kCases + "neuro_thrombectomy_m1_stentretriever.actions", *loaded.value);
  ASSERT_TRUE(script) << (script ? "" : script.error().message);
  const std::string path = fixtures::temp_path("session_test", "stent_retriever_m1.cbxrec");
  Metrics live;
  {
    Session s(std::move(loaded.value), std::move(*script));
    ASSERT_TRUE(s.thrombectomy());
    ASSERT_TRUE(s.record_to(path));
    const std::size_t stent = s.simulator().find_tool("stent");
    double integration = 0.0;
    while (!s.over()) {
      s.step_virtual(1000);
      integration = std::max(integration, s.thrombectomy()->stent_integration(stent));
    }
    std::printf("integration reached %.3f\n", integration);
    EXPECT_GT(integration, 0.9);
    live = s.metrics();
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
  EXPECT_GT(t.retrieval_force_peak_N, 0.1);
  EXPECT_LT(t.retrieval_force_peak_N, 5.0);
  const ReplayResult r = replay_record(path);
  ASSERT_TRUE(r.error.empty()) << r.error;
  EXPECT_FALSE(r.mismatch);
  ASSERT_TRUE(r.metrics.thrombectomy);
  EXPECT_EQ(*r.metrics.thrombectomy, t);
}

}  // namespace
}  // namespace cathbox::session
