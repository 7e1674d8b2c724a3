// The bundled thrombectomy cases as sessions load with their clots occluding the flow model
// (the fluoroscopy's contrast rides on it), and a bad clot is refused at load naming its line.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "flow/flow_network.hpp"
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

}  // namespace
}  // namespace cathbox::session
