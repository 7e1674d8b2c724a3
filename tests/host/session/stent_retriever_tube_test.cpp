// The stent retriever's whole pass in the default run, small: a Y of straight tubes (3.6 mm
// parent, a 2.8 mm branch straight on, M1-sized, and a 2.4 mm side branch), a 10 mm red-cell-
// rich clot in the straight branch; balloon guide > microcatheter > a 4 x 20 mm stent retriever
// (no microwire: the branch runs straight on). The stent is unsheathed across the clot,
// integrates it (embedding time cut to 0.5 s), the microcatheter goes into the guide and the
// stent is pulled into the guide under flow arrest: the clot comes with it and the branch's
// territory reperfuses. The bundled M1 case (the same pass after a real access, ~86 s of CPU)
// is test_session_stent_retriever, labelled `long`.
// Sources: eTICI bands, Liebeskind et al., J NeuroIntervent Surg 2019 (a complete removal is
// eTICI 3, 100 % of the territory); the removal force, 0.24 +- 0.01 N for a Solitaire 4 x 20 mm in
// a straight model, up to 1.6 N in the most tortuous (Front Neurol 2024;15:1486738), to which the
// dragged clot's wall friction adds.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "flow/reperfusion.hpp"
#include "session/session.hpp"
#include "session/thrombectomy_unit.hpp"
#include "session_fixtures.hpp"
#include "stent_tube_case.hpp"

namespace cathbox::session {
namespace {

// The distance from `p` to the polyline through `nodes`.
double off_polyline_mm(const std::vector<glm::vec3>& drawn, const glm::vec3& p) {
  const std::vector<glm::dvec3> nodes(drawn.begin(), drawn.end());
  double best = 1e9;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
    const glm::dvec3 ab = nodes[i + 1] - nodes[i];
    const double len2 = glm::dot(ab, ab);
    const double f = len2 > 0.0 ? std::clamp(glm::dot(glm::dvec3(p) - nodes[i], ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::distance(glm::dvec3(p), nodes[i] + f * ab));
  }
  return best;
}

constexpr const char* kScript = fixtures::kStentTubeScript;

TEST(StentRetrieverTube, DeployedAcrossTheClotItIntegratesItAndRetrievesItIntoTheGuide) {
  SessionCaseLoad loaded = load_session_case(fixtures::write_stent_tube_case());
  ASSERT_TRUE(loaded) << loaded.error().message;
  std::unique_ptr<Hand> script = fixtures::script_hand(*loaded.value(), kScript);
  ASSERT_TRUE(script);
  Session s(std::move(loaded.value()), std::move(script));
  ASSERT_TRUE(s.thrombectomy());
  ASSERT_TRUE(s.metrics().thrombectomy);
  EXPECT_EQ(s.metrics().thrombectomy->etici_final, flow::Etici::k0) << "occluded before the pass";
  const std::size_t stent = s.simulator().find_tool("stent");
  std::string lines;
  double integration = 0.0;
  // The published snapshot's clot, tick by tick: in place, engaged by the stent, dragged with
  // it (its face moved with the stent's tip), then removed.
  std::vector<ClotState> states;
  float dragged_mm = 0.0F;
  glm::vec3 face_mm(0.0F);
  {
    s.snapshots().acquire();
    const SceneSnapshot& first = s.snapshots().read_slot();
    ASSERT_EQ(first.clot_count, 1);
    face_mm = first.clots[0].start_mm;
    EXPECT_NEAR(first.clots[0].start_mm.z, 36.0F, 0.5F) << "the clot's face, 6 mm into the branch at z = 30";
    EXPECT_NEAR(glm::distance(first.clots[0].start_mm, first.clots[0].end_mm), 10.0F, 0.5F);
    EXPECT_NEAR(first.clots[0].radius_mm, 1.4F, 0.05F);
    // Fixed for the run: the stent's length and its push wire's radius (0.4 mm od).
    EXPECT_EQ(first.tools[stent].stent_length_mm, 20.0F);
    EXPECT_FLOAT_EQ(first.tools[stent].wire_radius_mm, 0.2F);
    EXPECT_EQ(first.tools[0].stent_length_mm, 0.0F) << "the guide has no stent";
  }
  float widest_mm = 0.0F;
  int removed = 0;
  int count_after = -1;
  double off_path_mm = 0.0;
  while (!s.over()) {
    s.step_virtual(100);
    integration = std::max(integration, s.thrombectomy()->stent_integration(stent));
    s.snapshots().acquire();
    const SceneSnapshot& snap = s.snapshots().read_slot();
    if (snap.clot_count > 0 && (states.empty() || states.back() != snap.clots[0].state)) states.push_back(snap.clots[0].state);
    if (snap.clot_count > 0 && snap.clots[0].state == ClotState::kDragged) {
      dragged_mm = std::max(dragged_mm, glm::distance(face_mm, snap.clots[0].start_mm));
      // Drawn along the stent's path: every point of its axis on the stent's nodes' polyline (as
      // the same tick's snapshot draws them).
      for (const glm::vec3& a : snap.clots[0].axis_mm) off_path_mm = std::max(off_path_mm, off_polyline_mm(snap.tools[stent].nodes_mm, a));
      EXPECT_GT(glm::distance(snap.clots[0].start_mm, snap.clots[0].end_mm), 9.0F) << "it keeps its length on the stent";
    }
    widest_mm = std::max(widest_mm, snap.tools[stent].radius_mm);
    EXPECT_FLOAT_EQ(snap.tools[stent].wire_radius_mm, 0.2F) << "the push wire, whatever the stent does";
    removed = snap.clots_removed;
    count_after = snap.clot_count;
    for (LogEvent e; s.events().pop(e);) lines += std::string(e.text.data()) + "\n";
  }
  std::printf("%s", lines.c_str());
  EXPECT_NE(lines.find("stent retriever across the clot"), std::string::npos);
  EXPECT_NE(lines.find("the clot comes with the stent"), std::string::npos);
  EXPECT_GT(integration, 0.9);
  EXPECT_EQ(states, (std::vector<ClotState>{ClotState::kInPlace, ClotState::kEngaged, ClotState::kDragged}));
  EXPECT_GT(dragged_mm, 5.0F) << "the dragged clot moves with the stent";
  EXPECT_LT(off_path_mm, 0.01) << "a dragged clot is drawn on the stent's path";
  EXPECT_EQ(removed, 1);
  EXPECT_EQ(count_after, 0) << "a removed clot is no longer drawn";
  EXPECT_GT(widest_mm, 1.0F) << "the expanded stent drawn wider than its push wire";
  std::printf("snapshot clot: dragged %.1f mm before it came out\n", static_cast<double>(dragged_mm));
  const Metrics m = s.metrics();
  ASSERT_TRUE(m.thrombectomy);
  const ThrombectomyFigures& t = *m.thrombectomy;
  std::printf("tube: %d pass(es), eTICI %s (%.0f %%), %d emboli, retrieval force %.3f N\n", t.passes,
              std::string(flow::etici_label(t.etici_final)).c_str(), t.reperfused_pct_final, t.emboli, t.retrieval_force_peak_N);
  EXPECT_EQ(t.passes, 1);
  EXPECT_EQ(t.stent_passes, 1);
  EXPECT_EQ(t.etici_final, flow::Etici::k3);
  EXPECT_TRUE(t.first_pass_effect);
  EXPECT_EQ(t.emboli, 0);
  EXPECT_GE(t.time_to_reperfusion_us, 0);
  // At least the straight model's published removal force, below the most tortuous one's.
  EXPECT_GT(t.retrieval_force_peak_N, 0.2);
  EXPECT_LT(t.retrieval_force_peak_N, 1.6);
}

// Solumbra's end in the same Y: the clot's face 1 mm into the branch, the guide on the pump. The
// stent is deployed across the clot, the microcatheter drawn into the guide, the aspirating
// guide advanced to 1.5 mm short of the face (within kFaceReach_mm: the vacuum engages it) and
// the stent pulled into it: the stent's pass takes the thrombus, so the vacuum holds nothing
// any more; switching aspiration off afterwards is no lost pass and no grip stays on the tip.
constexpr const char* kSolumbraScript =
    "0 select guide\n0 insert_to 20 at 40\n"
    "0 select microcatheter\n0 insert_to 56 at 40\n"
    "1500 select stent\n1500 insert_to 50 at 50\n"
    "2500 select microcatheter\n2500 insert_by -30 at 20\n"
    "4000 insert_to 15 at 40\n"
    "4400 select guide\n4400 aspiration on\n4400 insert_to 29.5 at 20\n"
    "5000 select stent\n5000 insert_to 10 at 20\n"
    "7100 select guide\n7100 aspiration off\n"
    "7200 end\n";

TEST(StentRetrieverTube, AStentPassIntoTheEngagedCatheterEndsTheVacuumsHoldOnTheClotItTook) {
  SessionCaseLoad loaded = load_session_case(fixtures::write_stent_tube_case("clot 2 1 10 red=60 fibrin=30\n", "  aspiration pump\n"));
  ASSERT_TRUE(loaded) << loaded.error().message;
  std::unique_ptr<Hand> script = fixtures::script_hand(*loaded.value(), kSolumbraScript);
  ASSERT_TRUE(script);
  Session s(std::move(loaded.value()), std::move(script));
  ASSERT_TRUE(s.thrombectomy());
  const std::size_t guide = s.simulator().find_tool("guide");
  std::string lines;
  bool engaged_before_pass = false;
  int held_after_pass_ticks = 0;  // engaged, or a grip on the guide's tip, after the pass
  while (!s.over()) {
    s.step_virtual(100);
    const ThrombectomyUnit& unit = *s.thrombectomy();
    if (unit.figures().passes == 0) engaged_before_pass = engaged_before_pass || unit.engaged();
    if (unit.figures().passes == 1 && (unit.engaged() || unit.aspiration_grip_mN(guide) != 0.0)) ++held_after_pass_ticks;
    for (LogEvent e; s.events().pop(e);) lines += std::string(e.text.data()) + "\n";
  }
  std::printf("%s", lines.c_str());
  EXPECT_TRUE(engaged_before_pass) << "the aspirating guide's tip engages the clot's face";
  EXPECT_EQ(held_after_pass_ticks, 0) << "a vacuum held on a clot already taken out";
  EXPECT_NE(lines.find("holds no clot now"), std::string::npos);
  EXPECT_EQ(lines.find("lets the clot go"), std::string::npos) << "no clot left to let go";
  const ThrombectomyFigures& t = *s.metrics().thrombectomy;
  EXPECT_EQ(t.passes, 1);
  EXPECT_EQ(t.stent_passes, 1);
  EXPECT_EQ(s.thrombectomy()->clots().size(), 0U);
}

}  // namespace
}  // namespace cathbox::session
