// The trainer's fluoroscopy front end (fluoro_inputs_from_snapshot): what a session's snapshot
// gives the fluoroscopic view (pulses at the rate, tools with their platinum markers, a stent
// retriever's bands and its expanded stent, released coils). No GL.
#include <gtest/gtest.h>

#include <utility>
#include <vector>

#include <glm/glm.hpp>

#include "app/fluoro_frontend.hpp"

namespace cathbox::app {
namespace {

// The trainer's front end today: a snapshot's tools under continuous 15 pulses/s fluoroscopy.
TEST(FluoroFrontend, ASnapshotGivesPulsesAtTheRateAndItsToolsWithPlatinumTips) {
  session::SceneSnapshot snap;
  snap.tool_count = 2;
  snap.tools[0].nodes_mm = {{0, 0, 100}, {0, 0, 110}};
  snap.tools[0].radius_mm = 0.18F;
  snap.tools[1].nodes_mm = {{1, 0, 100}, {1, 0, 105}};
  snap.tools[1].radius_mm = 0.6F;
  SnapshotFluoroSettings settings;
  settings.pose.lao_deg = 30.0;
  for (const auto& [time_us, pulse] : {std::pair{0LL, 0LL}, std::pair{66'666LL, 0LL}, std::pair{66'667LL, 1LL}, std::pair{1'000'000LL, 15LL}}) {
    snap.sim_time_us = time_us;
    const FluoroInputs in = fluoro_inputs_from_snapshot(snap, settings);
    EXPECT_EQ(in.image.pulse, pulse) << time_us;
    EXPECT_EQ(in.shown.pulse, pulse);
    EXPECT_TRUE(in.image.beam_on);
    EXPECT_EQ(in.pose, settings.pose);
  }
  const FluoroInputs in = fluoro_inputs_from_snapshot(snap, settings);
  ASSERT_EQ(in.shown.tools.size(), 2U);
  EXPECT_EQ(in.shown.tools[1].nodes_mm, snap.tools[1].nodes_mm);
  EXPECT_EQ(in.shown.tools[1].radius_mm, 0.6F);
  ASSERT_EQ(in.shown.tools[0].markers.size(), 1U);
  EXPECT_EQ(in.shown.tools[0].markers[0].material, flow::XrayMaterial::kPlatinum);
  EXPECT_EQ(in.shown.tools[0].markers[0].length_mm, settings.tip_marker_mm);
  EXPECT_EQ(check_fluoro_inputs(in, 0), "");
}

// A stent retriever's push wire: no 30 mm platinum tip, a 1 mm platinum band at each end of
// its stent instead (the end markers of Solitaire- and Trevo-type devices).
TEST(FluoroFrontend, AStentRetrieverShowsItsTwoEndMarkersNotAPlatinumTip) {
  session::SceneSnapshot snap;
  snap.tool_count = 2;
  snap.tools[0].nodes_mm = {{0, 0, 100}, {0, 0, 110}};
  snap.tools[1].nodes_mm = {{1, 0, 100}, {1, 0, 130}};
  snap.tools[1].stent_length_mm = 20.0F;
  const FluoroInputs in = fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{});
  ASSERT_EQ(in.shown.tools.size(), 2U);
  ASSERT_EQ(in.shown.tools[0].markers.size(), 1U);
  EXPECT_EQ(in.shown.tools[0].markers[0].length_mm, SnapshotFluoroSettings{}.tip_marker_mm);
  const std::vector<FluoroMarker>& m = in.shown.tools[1].markers;
  ASSERT_EQ(m.size(), 2U);
  EXPECT_EQ(m[0].from_tip_mm, 0.0);
  EXPECT_EQ(m[0].length_mm, kStentMarker_mm);
  EXPECT_EQ(m[1].from_tip_mm, 20.0 - kStentMarker_mm);
  EXPECT_EQ(m[1].length_mm, kStentMarker_mm);
  EXPECT_EQ(m[1].material, flow::XrayMaterial::kPlatinum);
  EXPECT_EQ(check_fluoro_inputs(in, 0), "");
}

// Expanded (the push wire's narrowest node below its widest), the push wire is drawn at its own
// radius up to the stent, and of the stent only its platinum markers, as a real device shows:
// one on the axis at the stent's proximal end, three at the struts' distal ends on the expanded
// radius; no strut body as wide as the stent.
TEST(FluoroFrontend, AnExpandedStentShowsOnlyItsMarkersBeyondItsThinPushWire) {
  session::SceneSnapshot snap;
  snap.tool_count = 1;
  for (int z = 0; z <= 60; z += 5) snap.tools[0].nodes_mm.push_back({0.0F, 0.0F, 100.0F + static_cast<float>(z)});
  snap.tools[0].stent_length_mm = 20.0F;
  snap.tools[0].radius_mm = 1.3F;
  snap.tools[0].wire_radius_mm = 0.2F;
  const FluoroInputs in = fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{});
  ASSERT_EQ(in.shown.tools.size(), 1U + 1U + static_cast<std::size_t>(kStentDistalMarkers));
  const FluoroTool& wire = in.shown.tools[0];
  EXPECT_EQ(wire.radius_mm, 0.2F);
  EXPECT_EQ(wire.material, flow::XrayMaterial::kNitinol);
  EXPECT_TRUE(wire.markers.empty());
  ASSERT_EQ(wire.nodes_mm.size(), 9U);  // 100 ... 140 mm: the stent's 20 mm begin at 140
  EXPECT_EQ(wire.nodes_mm.back(), glm::vec3(0.0F, 0.0F, 140.0F));
  const FluoroTool& proximal = in.shown.tools[1];
  ASSERT_EQ(proximal.nodes_mm.size(), 2U);
  EXPECT_EQ(proximal.nodes_mm.front(), glm::vec3(0.0F, 0.0F, 140.0F));
  EXPECT_NEAR(proximal.nodes_mm.back().z, 140.0F + static_cast<float>(kStentMarker_mm), 1e-4F);
  for (std::size_t k = 1; k < in.shown.tools.size(); ++k) {
    const FluoroTool& m = in.shown.tools[k];
    EXPECT_EQ(m.material, flow::XrayMaterial::kPlatinum);
    EXPECT_EQ(m.radius_mm, static_cast<float>(kStentMarkerRadius_mm));
    EXPECT_LT(m.radius_mm, snap.tools[0].radius_mm) << "no tool as wide as the stent";
    if (k < 2) continue;
    // The distal markers: the last mm of the stent, on its expanded radius, 120 degrees apart.
    ASSERT_EQ(m.nodes_mm.size(), 2U);
    EXPECT_NEAR(m.nodes_mm.front().z, 159.0F, 1e-4F);
    EXPECT_NEAR(m.nodes_mm.back().z, 160.0F, 1e-4F);
    EXPECT_NEAR(glm::length(glm::vec2(m.nodes_mm.back())), 1.3F - static_cast<float>(kStentMarkerRadius_mm), 1e-4F);
    const glm::vec2 a = glm::normalize(glm::vec2(m.nodes_mm.back()));
    const glm::vec2 b = glm::normalize(glm::vec2(in.shown.tools[k == 2 ? 3 : 2].nodes_mm.back()));
    EXPECT_NEAR(glm::dot(a, b), -0.5F, 1e-4F);
  }
  EXPECT_EQ(check_fluoro_inputs(in, 0), "");
  // Crimped (no node wider than the wire) it stays one tool with a band at each end.
  snap.tools[0].radius_mm = 0.2F;
  const FluoroInputs crimped = fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{});
  ASSERT_EQ(crimped.shown.tools.size(), 1U);
  EXPECT_EQ(crimped.shown.tools[0].markers.size(), 2U);
}

// Released coils (SceneSnapshot::coils) reach the image as platinum tools after the case's
// tools: live in continuous fluoroscopy, at the shown pulse with the session's unit.
TEST(FluoroFrontend, ReleasedCoilsArePlatinumToolsAfterTheTools) {
  session::SceneSnapshot snap;
  snap.tool_count = 1;
  snap.tools[0].nodes_mm = {{0, 0, 100}, {0, 0, 110}};
  snap.coil_count = 1;
  snap.coils[0].nodes_mm = {{2, 0, 100}, {3, 1, 100}, {2, 2, 100}};
  snap.coils[0].radius_mm = 0.125F;
  FluoroInputs in = fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{});
  ASSERT_EQ(in.shown.tools.size(), 2U);
  EXPECT_EQ(in.shown.tools[0].material, flow::XrayMaterial::kNitinol);
  EXPECT_EQ(in.shown.tools[1].material, flow::XrayMaterial::kPlatinum);
  EXPECT_TRUE(in.shown.tools[1].markers.empty());
  EXPECT_EQ(in.shown.tools[1].nodes_mm, snap.coils[0].nodes_mm);
  EXPECT_EQ(in.shown.tools[1].radius_mm, 0.125F);
  // With the session's unit: the coil as it was at the shown pulse.
  snap.fluoro.available = true;
  snap.fluoro.pulse_tool_count = 1;
  snap.fluoro.pulse_tool_nodes_mm[0] = snap.tools[0].nodes_mm;
  snap.fluoro.pulse_coil_count = 1;
  snap.fluoro.pulse_coil_nodes_mm[0] = {{5, 0, 100}, {6, 0, 100}};
  in = fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{});
  ASSERT_EQ(in.shown.tools.size(), 2U);
  EXPECT_EQ(in.shown.tools[1].nodes_mm, snap.fluoro.pulse_coil_nodes_mm[0]);
  EXPECT_EQ(in.shown.tools[1].material, flow::XrayMaterial::kPlatinum);
  EXPECT_EQ(check_fluoro_inputs(in, 0), "");
}

}  // namespace
}  // namespace cathbox::app
