// The bundled thrombectomy cases as sessions load with their clots occluding the flow model
// (the fluoroscopy's contrast rides on it), and a bad clot is refused at load naming its line.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "flow/flow_network.hpp"
#include "session/action_script_hand.hpp"
#include "session/session_case.hpp"

namespace cathbox::session {
namespace {

double left_mca_ml_min(const flow::FlowNetwork& net) {
  double q = 0.0;
  for (const flow::Terminal& t : net.terminals()) {
    if (net.model().segments[t.segment].name.rfind("left_middle_cerebral_m2", 0) == 0) q += t.flow_ml_min;
  }
  return q;
}

TEST(ThrombectomyCase, ClotsOccludeTheFlowAtLoad) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  SessionCaseLoad open = load_session_case(dir + "neuro.case");
  ASSERT_TRUE(open) << open.error().message;
  const double baseline = left_mca_ml_min(*open.value()->flow);
  ASSERT_GT(baseline, 50.0);
  for (const char* name : {"neuro_thrombectomy_m1.case", "neuro_thrombectomy_ica_t.case"}) {
    SessionCaseLoad loaded = load_session_case(dir + name);
    ASSERT_TRUE(loaded) << loaded.error().message;
    ASSERT_TRUE(loaded.value()->flow) << name;
    EXPECT_FALSE(loaded.value()->flow->clots().empty()) << name;
    EXPECT_LT(left_mca_ml_min(*loaded.value()->flow), 0.05 * baseline) << name;
  }
}

TEST(ThrombectomyCase, ABadClotIsRefusedAtLoadNamingItsLine) {
  const std::string path = testing::TempDir() + "bad_clot.case";
  {
    std::ofstream f(path);
    f << "cathbox-case 1\nvessel " << CATHBOX_SOURCE_DIR << "/cases/neuro.hclm\nclot 22 10 13\n";
  }
  SessionCaseLoad loaded = load_session_case(path);
  EXPECT_FALSE(loaded);
  EXPECT_NE(loaded.error().message.find("bad_clot.case:3: clot: runs past the end of segment 22"), std::string::npos) << loaded.error().message;
  std::remove(path.c_str());
}

// Each bundled thrombectomy script on the case it is run with (the technique runs are the
// CTest entries thrombectomy_script_* in tests/host/cli, labelled long): it parses and every
// tool it selects is in the case. Every neuro_thrombectomy_*.actions in cases/ is listed here.
TEST(ThrombectomyCase, EveryScriptLoadsOnItsCase) {
  const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
  const std::vector<std::pair<std::string, std::string>> runs{
      {"m1", "m1_access"},
      {"m1", "m1_adapt"},
      {"m1_stentretriever", "m1_stentretriever"},
      {"m1_stentretriever", "m1_stentretriever_careless"},
      {"m1_solumbra", "m1_solumbra"},
      {"ica_t", "ica_t"},
      {"ica_t_stentretriever", "ica_t_stentretriever"},
      {"ica_t_solumbra", "ica_t_solumbra"},
  };
  std::set<std::string> listed;
  for (const auto& [case_name, script_name] : runs) {
    const std::string script = "neuro_thrombectomy_" + script_name + ".actions";
    listed.insert(script);
    SessionCaseLoad loaded = load_session_case(dir + "neuro_thrombectomy_" + case_name + ".case");
    ASSERT_TRUE(loaded) << loaded.error().message;
    const auto hand = ActionScriptHand::load(dir + script, *loaded.value());
    EXPECT_TRUE(hand) << script << ": " << (hand ? std::string() : hand.error().message);
  }
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("neuro_thrombectomy_", 0) == 0 && entry.path().extension() == ".actions") {
      EXPECT_TRUE(listed.count(name) == 1) << name << " is run with no case here";
    }
  }
}

// A script's `aspiration` on a tool the case gives no vacuum source is refused at load, naming
// its line: the Solumbra case's microcatheter selected when the pump is switched on (a run did
// this and went on with no vacuum: the sheared rim embolized, eTICI 2b50).
TEST(ThrombectomyCase, AnAspirationOnAToolWithNoVacuumIsRefusedAtLoad) {
  SessionCaseLoad loaded = load_session_case(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_thrombectomy_m1_solumbra.case");
  ASSERT_TRUE(loaded) << loaded.error().message;
  const std::vector<tool::ScriptPlayer::ToolInfo> tools = ActionScriptHand::tool_infos(*loaded.value());
  const auto made = [&](const char* text) {
    const tool::ScriptParse p = tool::parse_script(text, "s.actions");
    EXPECT_TRUE(p) << p.error().message;
    const auto hand = ActionScriptHand::make(*p, "s.actions", tools, 0);
    return hand ? std::string("ok") : hand.error().message;
  };
  EXPECT_EQ(made("0 select aspiration\n1 aspiration on\n"), "ok");
  EXPECT_EQ(made("0 select microcatheter\n1 aspiration on\n"),
            "s.actions:2: aspiration: tool 'microcatheter' has no vacuum source (the case's `aspiration` names the catheter that has)");
}

}  // namespace
}  // namespace cathbox::session
