// What the fluoroscopic view (FluoroRenderer) shows of a scene, under Xvfb (llvmpipe) on the
// bundled neuro case (fluoro_render_fixture.hpp): the wire with its platinum tip, the vessels
// before and after an injection in the right internal carotid, the digital subtraction, the
// roadmap, the C-arm's angle, a released coil. Positions are checked against the C-arm's own
// projection (CArm::project_px); comparisons of two renders differ only in what is tested (noise
// off, or the same pulse). Screenshots: fluoro_*.png in the build folder of this test.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "fluoro_render_fixture.hpp"

namespace cathbox::app::fluoro_test {
namespace {

TEST_F(FluoroRenderTest, TheWireIsAThinDarkLineAtItsProjectedPositionWithADarkerPlatinumTip) {
  renderer_.set_display({.noise = false});
  const FluoroTool wire = wire_in_right_ica();
  const Image without = render(live(3, no_contrast(), {}));
  const Image with = render(live(3, no_contrast(), {wire}));
  renderer_.set_display({});
  save(render(live(3, no_contrast(), {wire})), "fluoro_wire.png");

  const flow::CArm carm{flow::CArmPose{}};
  std::vector<glm::dvec2> line;
  for (const glm::vec3& n : wire.nodes_mm) line.push_back(carm.project_px(glm::dvec3(n), kSize, kSize));
  // Every changed pixel lies on the projected wire; the wire's pixels are darker.
  int changed = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      if (with.pixel(x, y)[0] == without.pixel(x, y)[0]) continue;
      ++changed;
      EXPECT_LT(distance_to_polyline({x + 0.5, y + 0.5}, line), 2.5) << "pixel " << x << "," << y << " changed";
    }
  }
  EXPECT_GT(changed, 60);
  int darker = 0;
  int shaft_nodes = 0;
  for (std::size_t i = 2; i + 6 < line.size(); ++i, ++shaft_nodes) darker += grey(with, line[i]) < grey(without, line[i]) - 3 ? 1 : 0;
  EXPECT_GE(darker, shaft_nodes * 4 / 5) << "shaft pixels darker";
  // The platinum tip is much darker than the nitinol shaft.
  const double shaft = mean_change(without, with, carm, {wire.nodes_mm.begin() + 10, wire.nodes_mm.begin() + 40});
  const double tip = mean_change(without, with, carm, {wire.nodes_mm.back() - 0.5F * (wire.nodes_mm.back() - wire.nodes_mm[wire.nodes_mm.size() - 2])});
  EXPECT_LT(shaft, -5.0);
  EXPECT_LT(tip, 2.0 * shaft) << "tip " << tip << " shaft " << shaft;
}

TEST_F(FluoroRenderTest, BeforeAnInjectionTheVesselsAreNotVisible) {
  renderer_.set_display({.noise = false});
  const Image with_vessel = render(live(1, no_contrast(), {}));
  FluoroRenderer bare;
  const base::Status<> bare_ready = bare.init();
  ASSERT_TRUE(bare_ready) << bare_ready.error().message;
  bare.set_display({.noise = false});
  EXPECT_EQ(bare.render(Viewport{0, 0, kSize, kSize}, kSize, live(1, no_contrast(), {})), "");
  const Image no_vessel = FrameCapture::read_back_buffer(kSize, kSize);
  EXPECT_EQ(with_vessel.pixels, no_vessel.pixels);
  // The phantom is there: not a black or white field.
  const flow::CArm carm{flow::CArmPose{}};
  const glm::dvec2 c = carm.project_px(carm.isocenter_mm(), kSize, kSize);
  EXPECT_GT(grey(with_vessel, c), 40);
  EXPECT_LT(grey(with_vessel, c), 215);
  renderer_.set_display({});
  save(render(live(1, no_contrast(), {})), "fluoro_before_injection.png");
}

TEST_F(FluoroRenderTest, InjectingTheRightIcaDarkensItsTerritoryNotTheLeftIca) {
  flow::ContrastTransport& t = *neuro_->transport;
  t.reset();
  const std::vector<float> before = cell_iodine(t);
  ASSERT_TRUE(t.inject({neuro_->right_ica, 0.3 * t.locator().length_mm(neuro_->right_ica), 0.0}, {6.0, 3.0, 300.0}).empty());
  for (int i = 0; i < 150; ++i) t.step();  // 1.5 s
  const std::vector<float> after = cell_iodine(t);
  t.reset();

  renderer_.set_display({.noise = false});
  const Image pre = render(live(10, before, {}));
  const Image post = render(live(10, after, {}));
  const flow::CArm carm{flow::CArmPose{}};
  const double right = mean_change(pre, post, carm, centreline(neuro_->right_ica, 0.4, 0.95, 40));
  const double left = mean_change(pre, post, carm, centreline(neuro_->left_ica, 0.05, 0.95, 60));
  EXPECT_LT(right, -12.0) << "right ICA downstream of the tip darkens";
  int brighter = 0;
  for (std::size_t i = 0; i < pre.pixels.size(); i += 3) {
    if (post.pixels[i] > pre.pixels[i] + 1) {
      if (brighter++ < 5) ADD_FAILURE() << "contrast brightened pixel " << (i / 3) % kSize << "," << (i / 3) / kSize << ": " << int(pre.pixels[i]) << " -> " << int(post.pixels[i]);
    }
  }
  EXPECT_EQ(brighter, 0) << "contrast only absorbs";
  EXPECT_NEAR(left, 0.0, 0.5) << "left ICA unchanged";
  // With noise the darkening still stands out of it.
  renderer_.set_display({});
  const Image noisy = render(live(10, after, {}));
  const Image noisy_pre = render(live(10, before, {}));
  EXPECT_LT(mean_change(noisy_pre, noisy, carm, centreline(neuro_->right_ica, 0.4, 0.95, 40)), -10.0);
  for (std::size_t i = 0; i < noisy.pixels.size(); i += 3) {
    ASSERT_LE(noisy.pixels[i], noisy_pre.pixels[i] + 1) << "pixel " << (i / 3) % kSize << "," << (i / 3) / kSize;
  }
  save(noisy, "fluoro_right_ica_injection.png");

  // Digital subtraction: the run frame minus its contrast-free mask shows only the contrast.
  FluoroInputs dsa = live(11, after, {});
  dsa.shown.mode = flow::ExposureMode::kSubtractionRun;
  dsa.image.mode = flow::ExposureMode::kSubtractionRun;
  dsa.image.run = 1;
  dsa.image.mask_pulse = 9;
  dsa.mask = {9, flow::ExposureMode::kFluoroscopy, before, {}};
  save(render(dsa), "fluoro_dsa.png");
  renderer_.set_display({.noise = false});
  const Image sub = render(dsa);
  const int background = static_cast<int>(std::lround(255.0 * FluoroDisplay{}.dsa_background));
  for (const glm::dvec2& px : in_image(carm, centreline(neuro_->right_ica, 0.4, 0.95, 40))) {
    EXPECT_LT(grey(sub, px), background - 30) << px.x << "," << px.y;
  }
  for (const glm::dvec2& px : in_image(carm, centreline(neuro_->left_ica, 0.05, 0.95, 40))) {
    EXPECT_NEAR(grey(sub, px), background, 1) << px.x << "," << px.y;
  }
}

TEST_F(FluoroRenderTest, TheRoadmapShowsTheInjectedTerritoryWithThePedalOff) {
  flow::ContrastTransport& t = *neuro_->transport;
  t.reset();
  const std::vector<float> mask = cell_iodine(t);
  ASSERT_TRUE(t.inject({neuro_->right_ica, 0.3 * t.locator().length_mm(neuro_->right_ica), 0.0}, {6.0, 3.0, 300.0}).empty());
  for (int i = 0; i < 150; ++i) t.step();
  const std::vector<float> peak = cell_iodine(t);
  t.reset();

  // The last image held (pedal up) with the wire in it; the run's peak as the roadmap.
  FluoroInputs held = live(30, no_contrast(), {wire_in_right_ica()});
  held.image.beam_on = false;
  ASSERT_TRUE(held.image.last_image_hold());
  const Image plain = render(held);
  held.image.roadmap_pulse = 21;
  held.roadmap = {21, flow::ExposureMode::kSubtractionRun, peak, {}};
  held.roadmap_mask = {20, flow::ExposureMode::kFluoroscopy, mask, {}};
  const Image road = render(held);
  save(road, "fluoro_roadmap.png");
  const flow::CArm carm{flow::CArmPose{}};
  // Same pulse, same noise: the difference is the roadmap (and its own frames' noise).
  EXPECT_GT(mean_change(plain, road, carm, centreline(neuro_->right_ica, 0.65, 0.95, 30)), 25.0) << "right ICA bright";
  EXPECT_NEAR(mean_change(plain, road, carm, centreline(neuro_->left_ica, 0.05, 0.95, 60)), 0.0, 4.0);
  // The wire stays a dark line inside the bright roadmap: darker than the roadmap without it.
  held.shown.tools.clear();
  const Image road_no_wire = render(held);
  const FluoroTool wire = wire_in_right_ica();
  int darker = 0;
  int nodes = 0;
  for (std::size_t i = 30; i + 6 < wire.nodes_mm.size(); ++i, ++nodes) {
    const glm::dvec2 px = carm.project_px(glm::dvec3(wire.nodes_mm[i]), kSize, kSize);
    darker += grey(road, px) < grey(road_no_wire, px) - 3 ? 1 : 0;
  }
  EXPECT_GE(darker, nodes * 3 / 4) << "wire darker inside the roadmap";
  EXPECT_LT(mean_change(road_no_wire, road, carm, {wire.nodes_mm.begin() + 30, wire.nodes_mm.end() - 6}), -5.0);
}

TEST_F(FluoroRenderTest, ChangingTheCArmAngleMovesTheProjectionAsTheGeometryPredicts) {
  renderer_.set_display({.noise = false});
  // A short platinum marker 40 mm off the isocentre.
  const glm::vec3 centre = glm::vec3(flow::CArm{}.isocenter_mm()) + glm::vec3(25.0F, 15.0F, 30.0F);
  FluoroTool marker;
  marker.radius_mm = 0.5F;
  marker.material = flow::XrayMaterial::kPlatinum;
  for (int i = 0; i <= 4; ++i) marker.nodes_mm.push_back(centre + glm::vec3(0.0F, 0.0F, -1.0F + 0.5F * static_cast<float>(i)));
  std::vector<glm::dvec2> seen;
  for (const auto& [lao, cranial] : {std::pair{0.0, 0.0}, std::pair{30.0, 0.0}, std::pair{-30.0, 20.0}, std::pair{90.0, 0.0}}) {
    flow::CArmPose pose;
    pose.lao_deg = lao;
    pose.cranial_deg = cranial;
    const Image a = render(live(5, no_contrast(), {}, pose));
    const Image b = render(live(5, no_contrast(), {marker}, pose));
    glm::dvec2 sum{0.0};
    double weight = 0.0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const double d = a.pixel(x, y)[0] - b.pixel(x, y)[0];
        if (d <= 0.0) continue;
        sum += d * glm::dvec2(x + 0.5, y + 0.5);
        weight += d;
      }
    }
    ASSERT_GT(weight, 0.0) << "LAO " << lao;
    const glm::dvec2 found = sum / weight;
    const glm::dvec2 predicted = flow::CArm(pose).project_px(glm::dvec3(centre), kSize, kSize);
    EXPECT_LT(glm::length(found - predicted), 1.0) << "LAO " << lao << " cranial " << cranial << ": found " << found.x << ","
                                                   << found.y << " predicted " << predicted.x << "," << predicted.y;
    seen.push_back(found);
    if (lao == 30.0) save(render(live(5, no_contrast(), {marker, wire_in_right_ica()}, pose)), "fluoro_lao30.png");
  }
  EXPECT_GT(glm::length(seen[1] - seen[0]), 10.0) << "LAO 30 moved the marker";
  EXPECT_GT(glm::length(seen[2] - seen[0]), 10.0);
}

// A released coil in the image, through the trainer's path (SceneSnapshot -> FluoroInputs ->
// renderer): a 4 mm loop of a 0.25 mm platinum coil at the right ICA darkens the pixels at its
// projected nodes, changes no pixel away from them, and is much darker than a nitinol wire of
// the same diameter laid on the same loop (platinum: mu/rho 6.95 cm2/g at 50 keV, 21.45 g/cm3,
// the table in sim/flow/src/xray_material.cpp). Without the coil the pixels stay background.
TEST_F(FluoroRenderTest, AReleasedCoilDarkensItsProjectedPixelsMuchMoreThanANitinolWire) {
  renderer_.set_display({.noise = false});
  const flow::CArm carm{flow::CArmPose{}};
  const flow::CenterlineLocator& loc = neuro_->transport->locator();
  const glm::dvec3 centre = loc.point_at(neuro_->right_ica, 0.5 * loc.length_mm(neuro_->right_ica));
  // A loop facing the beam (in the plane across the source-to-centre ray).
  const glm::dvec3 ray = glm::normalize(centre - carm.source_mm());
  const glm::dvec3 u = glm::normalize(glm::cross(ray, std::abs(ray.z) < 0.9 ? glm::dvec3(0, 0, 1) : glm::dvec3(1, 0, 0)));
  const glm::dvec3 v = glm::cross(ray, u);
  std::vector<glm::vec3> loop;
  for (int i = 0; i <= 48; ++i) {
    const double a = 2.0 * M_PI * i / 48.0;
    loop.emplace_back(centre + 2.0 * (std::cos(a) * u + std::sin(a) * v));
  }
  session::SceneSnapshot snap;
  snap.fluoro.available = true;
  snap.fluoro.image.pulse = 3;
  snap.fluoro.image.beam_on = true;
  snap.fluoro.iodine_mgI_ml = no_contrast();
  const Image background = render(fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{}));
  snap.coil_count = 1;
  snap.coils[0].radius_mm = 0.125F;
  snap.coils[0].nodes_mm = loop;
  snap.fluoro.pulse_coil_count = 1;
  snap.fluoro.pulse_coil_nodes_mm[0] = loop;
  const FluoroInputs with_coil = fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{});
  const Image coil = render(with_coil);
  FluoroInputs with_wire = with_coil;
  with_wire.shown.tools[0].material = flow::XrayMaterial::kNitinol;
  const Image wire = render(with_wire);
  snap.coil_count = 0;
  snap.fluoro.pulse_coil_count = 0;
  const Image again = render(fluoro_inputs_from_snapshot(snap, SnapshotFluoroSettings{}));
  renderer_.set_display({});
  save(render(with_coil), "fluoro_released_coil.png");

  std::vector<glm::dvec2> line;
  for (const glm::vec3& n : loop) line.push_back(carm.project_px(glm::dvec3(n), kSize, kSize));
  int changed = 0;
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      ASSERT_EQ(again.pixel(x, y)[0], background.pixel(x, y)[0]) << "without the coil, pixel " << x << "," << y;
      if (coil.pixel(x, y)[0] == background.pixel(x, y)[0]) continue;
      ++changed;
      EXPECT_LT(distance_to_polyline({x + 0.5, y + 0.5}, line), 2.5) << "pixel " << x << "," << y << " changed";
    }
  }
  EXPECT_GT(changed, 30);
  const double platinum = mean_change(background, coil, carm, loop);
  const double nitinol = mean_change(background, wire, carm, loop);
  EXPECT_LT(platinum, -20.0) << "the coil darkens its pixels";
  EXPECT_LT(platinum, 3.0 * nitinol) << "platinum " << platinum << ", nitinol " << nitinol;
  std::printf("released coil: mean grey change %.1f at its nodes (a nitinol wire on the same loop: %.1f), %d pixels changed\n",
              platinum, nitinol, changed);
}

}  // namespace
}  // namespace cathbox::app::fluoro_test
