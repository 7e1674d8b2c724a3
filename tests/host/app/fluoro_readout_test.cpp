// How the fluoroscopic view (FluoroRenderer) makes and reuses its images, under Xvfb (llvmpipe)
// on the bundled neuro case (fluoro_render_fixture.hpp): binned readout, the scenes' screen box,
// background projection, the phantom read through the framebuffer, bad inputs, and the vessel's
// vertex iodine from the transport cells. Each compares its images with a fresh renderer's or
// with another path's, pixel for pixel.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "fluoro_render_fixture.hpp"

namespace cathbox::app::fluoro_test {
namespace {

// Fluoroscopy read out binned (FluoroDisplay::fluoro_readout_pitch_mm coarser than a display
// pixel: here 0.86 mm against the test's 0.43 mm, a 256^2 image shown at 512^2): the image is
// made at the readout's pixels and scaled up bilinearly, and stays right: the right ICA's
// territory darkens as much as at full resolution and the left ICA not, contrast only absorbs,
// the wire stays on its projected line with its attenuation across the line kept (partial
// volume: fainter, wider), the noise per pixel falls (four times the quanta per pixel), a
// subtraction run frame is made at full resolution, and switching between the two readouts
// projects the phantom no more.
TEST_F(FluoroRenderTest, BinnedFluoroscopyKeepsTheImageAtTheReadoutsResolution) {
  const std::vector<float> before = no_contrast();
  const std::vector<float> after = right_ica_filled(150);
  const FluoroTool wire = wire_in_right_ica();
  const flow::CArm carm{flow::CArmPose{}};
  FluoroDisplay full{.noise = false};
  full.fluoro_readout_pitch_mm = 0.0F;
  FluoroDisplay binned = full;
  binned.fluoro_readout_pitch_mm = 0.86F;
  struct Set {
    Image pre, post, without, with;
  };
  const auto images = [&](const FluoroDisplay& d) {
    renderer_.set_display(d);
    Set s{render(live(20, before, {})), render(live(20, after, {})), render(live(21, before, {})), render(live(21, before, {wire}))};
    return s;
  };
  const Set f = images(full);
  EXPECT_EQ(renderer_.last_work().matrix_width, kSize);
  const Set b = images(binned);
  EXPECT_EQ(renderer_.last_work().matrix_width, kSize / 2);
  EXPECT_EQ(renderer_.last_work().matrix_height, kSize / 2);
  // Shown again (scaled into the window for the first four showings; from the fifth, a hold,
  // scaled once into a texture, then copied): the same picture every time.
  for (int again = 0; again < 6; ++again) {
    EXPECT_EQ(render(live(21, before, {wire})).pixels, b.with.pixels) << again;
    EXPECT_EQ(renderer_.last_work().composites, 0);
  }

  // Contrast: the right ICA darkens as at full resolution, the left not, nothing brightens.
  const auto right = [&](const Set& s) { return mean_change(s.pre, s.post, carm, centreline(neuro_->right_ica, 0.4, 0.95, 40)); };
  EXPECT_LT(right(b), -12.0);
  EXPECT_NEAR(right(b), right(f), 0.25 * std::abs(right(f)));
  EXPECT_NEAR(mean_change(b.pre, b.post, carm, centreline(neuro_->left_ica, 0.05, 0.95, 60)), 0.0, 0.5);
  for (std::size_t i = 0; i < b.pre.pixels.size(); i += 3) {
    ASSERT_LE(b.post.pixels[i], b.pre.pixels[i] + 1) << "pixel " << (i / 3) % kSize << "," << (i / 3) / kSize;
  }
  // The wire: every changed pixel within two readout pixels (and a half) of its projected line;
  // its total darkening (the integral across the line) as at full resolution.
  std::vector<glm::dvec2> line;
  for (const glm::vec3& n : wire.nodes_mm) line.push_back(carm.project_px(glm::dvec3(n), kSize, kSize));
  const auto darkening = [&](const Set& s, double within_px) {
    double sum = 0.0;
    for (int y = 0; y < kSize; ++y) {
      for (int x = 0; x < kSize; ++x) {
        const int d = s.with.pixel(x, y)[0] - s.without.pixel(x, y)[0];
        if (d == 0) continue;
        EXPECT_LT(distance_to_polyline({x + 0.5, y + 0.5}, line), within_px) << "pixel " << x << "," << y << " changed";
        sum += d;
      }
    }
    return sum;
  };
  const double wire_full = darkening(f, 2.5);
  const double wire_binned = darkening(b, 5.0);
  EXPECT_LT(wire_full, -500.0);
  EXPECT_NEAR(wire_binned, wire_full, 0.2 * std::abs(wire_full));
  EXPECT_LT(mean_change(b.without, b.with, carm, {wire.nodes_mm.begin() + 10, wire.nodes_mm.begin() + 40}), -2.0) << "shaft darker";
  std::printf("binned 2x2: right ICA %.1f (full %.1f) grey at its centreline; the wire's total darkening %.0f (full %.0f)\n", right(b),
              right(f), wire_binned, wire_full);

  // Noise: the binned pixel collects four pixels' quanta.
  const auto rms_noise = [&](FluoroDisplay d, const Image& clean) {
    d.noise = true;
    renderer_.set_display(d);
    return rms_difference(render(live(21, before, {wire})), clean);
  };
  const double noise_full = rms_noise(full, f.with);
  const double noise_binned = rms_noise(binned, b.with);
  EXPECT_GT(noise_binned, 0.5);
  EXPECT_LT(noise_binned, 0.6 * noise_full) << "binned " << noise_binned << " full " << noise_full;
  save(render(live(21, after, {wire})), "fluoro_binned.png");

  // A subtraction run frame is acquired at full resolution.
  renderer_.set_display(binned);
  FluoroInputs dsa = live(23, after, {});
  dsa.shown.mode = flow::ExposureMode::kSubtractionRun;
  dsa.image.run = 1;
  dsa.image.mask_pulse = 22;
  dsa.mask = {22, flow::ExposureMode::kFluoroscopy, before, {}};
  render(dsa);
  EXPECT_EQ(renderer_.last_work().matrix_width, kSize);
  // Both readouts' phantom projections are kept: switching between them projects nothing again.
  EXPECT_FALSE(renderer_.last_work().phantom_projected);
  EXPECT_EQ(render(live(21, before, {wire})).pixels, b.with.pixels);
  EXPECT_FALSE(renderer_.last_work().phantom_projected);

  // With background projection (the trainer) a C-arm move's first binned projection is followed
  // on a worker by the run's full one at the same pose: a subtraction run after the fluoroscopy
  // that placed the C-arm shows its own frames at once, not the last fluoroscopy image.
  renderer_.set_background_projection(true);
  flow::CArmPose lao20;
  lao20.lao_deg = 20.0;
  (void)render(live(24, before, {wire}, lao20));
  EXPECT_TRUE(renderer_.last_work().waiting_for_phantom);
  renderer_.finish_projection();
  (void)render(live(25, before, {wire}, lao20));
  EXPECT_TRUE(renderer_.last_work().phantom_projected);
  EXPECT_LT(renderer_.last_work().matrix_width, kSize);
  renderer_.finish_projection();
  FluoroInputs run = live(27, after, {}, lao20);
  run.shown.mode = flow::ExposureMode::kSubtractionRun;
  run.image.run = 2;
  run.image.mask_pulse = 26;
  run.mask = {26, flow::ExposureMode::kFluoroscopy, before, {}};
  (void)render(run);
  EXPECT_FALSE(renderer_.last_work().waiting_for_phantom) << "the run's phantom was projected after the fluoroscopy's";
  EXPECT_FALSE(renderer_.last_work().phantom_projected);
  EXPECT_EQ(renderer_.last_work().matrix_width, kSize);
  renderer_.set_background_projection(false);
}

// Only the scenes' screen box is cleared, drawn and read: a scene drawn after another elsewhere
// (the wire moved, contrast gone) leaves nothing of the first, and the image equals a fresh
// renderer's; the box of a wire is a small part of the image.
TEST_F(FluoroRenderTest, AScenesBoxLeavesNothingOfThePreviousScene) {
  renderer_.set_display({.noise = false});
  const std::vector<float> filled = right_ica_filled(150);
  FluoroTool left;
  left.nodes_mm = centreline(neuro_->left_ica, 0.05, 0.6, 60);
  left.radius_mm = 0.18F;
  (void)render(live(60, filled, {wire_in_right_ica()}));
  const Image second = render(live(61, no_contrast(), {left}));
  FluoroRenderer fresh;
  const base::Status<> fresh_ready = fresh.init();
  ASSERT_TRUE(fresh_ready) << fresh_ready.error().message;
  fresh.set_vessel(neuro_->vessel);
  fresh.set_display({.noise = false});
  EXPECT_EQ(fresh.render(Viewport{0, 0, kSize, kSize}, kSize, live(61, no_contrast(), {left})), "");
  EXPECT_EQ(FrameCapture::read_back_buffer(kSize, kSize).pixels, second.pixels);
  // A subtraction reads both scenes inside both boxes: the live scene (the left wire) must be
  // zero where the mask's box (the right wire) is, though it held the right wire before.
  FluoroInputs dsa = live(64, no_contrast(), {left});
  dsa.shown.mode = flow::ExposureMode::kSubtractionRun;
  dsa.image.run = 1;
  dsa.image.mask_pulse = 63;
  dsa.mask = {63, flow::ExposureMode::kFluoroscopy, no_contrast(), {wire_in_right_ica()}};
  (void)render(live(63, no_contrast(), {wire_in_right_ica()}));
  const Image sub = render(dsa);
  FluoroRenderer fresh_dsa;
  const base::Status<> fresh_dsa_ready = fresh_dsa.init();
  ASSERT_TRUE(fresh_dsa_ready) << fresh_dsa_ready.error().message;
  fresh_dsa.set_vessel(neuro_->vessel);
  fresh_dsa.set_display({.noise = false});
  EXPECT_EQ(fresh_dsa.render(Viewport{0, 0, kSize, kSize}, kSize, dsa), "");
  EXPECT_EQ(FrameCapture::read_back_buffer(kSize, kSize).pixels, sub.pixels);
  // The right wire shows in the subtraction (mask minus nothing: brighter than the background).
  const flow::CArm carm{flow::CArmPose{}};
  const FluoroTool right = wire_in_right_ica();
  const int background = static_cast<int>(std::lround(255.0 * FluoroDisplay{}.dsa_background));
  EXPECT_GT(grey(sub, carm.project_px(glm::dvec3(right.nodes_mm[30]), kSize, kSize)), background + 3);
  // Back to the first scene: the same image as the first time.
  const Image again = render(live(62, filled, {wire_in_right_ica()}));
  EXPECT_EQ(fresh.render(Viewport{0, 0, kSize, kSize}, kSize, live(62, filled, {wire_in_right_ica()})), "");
  EXPECT_EQ(FrameCapture::read_back_buffer(kSize, kSize).pixels, again.pixels);
}

// With background projection (the interactive trainer) a C-arm move keeps the last image until
// the new pose's phantom is projected, then shows exactly what projecting at once shows.
TEST_F(FluoroRenderTest, ABackgroundProjectionHoldsTheLastImageUntilTheNewPoseIsReady) {
  renderer_.set_display({.noise = false});
  renderer_.set_background_projection(true);
  flow::CArmPose lao30;
  lao30.lao_deg = 30.0;
  const Image ap = render(live(70, no_contrast(), {wire_in_right_ica()}));  // nothing shown yet: at once
  EXPECT_TRUE(renderer_.last_work().phantom_projected);
  const Image held = render(live(71, no_contrast(), {wire_in_right_ica()}, lao30));
  EXPECT_TRUE(renderer_.last_work().waiting_for_phantom);
  EXPECT_EQ(renderer_.last_work().scenes_accumulated, 0);
  EXPECT_EQ(held.pixels, ap.pixels) << "the last image stays while the C-arm's new view is computed";
  renderer_.finish_projection();
  const Image moved = render(live(71, no_contrast(), {wire_in_right_ica()}, lao30));
  EXPECT_FALSE(renderer_.last_work().waiting_for_phantom);
  EXPECT_TRUE(renderer_.last_work().phantom_projected);
  FluoroRenderer at_once;
  const base::Status<> at_once_ready = at_once.init();
  ASSERT_TRUE(at_once_ready) << at_once_ready.error().message;
  at_once.set_vessel(neuro_->vessel);
  at_once.set_display({.noise = false});
  EXPECT_EQ(at_once.render(Viewport{0, 0, kSize, kSize}, kSize, live(71, no_contrast(), {wire_in_right_ica()}, lao30)), "");
  EXPECT_EQ(FrameCapture::read_back_buffer(kSize, kSize).pixels, moved.pixels);
  EXPECT_NE(moved.pixels, ap.pixels);
}

// Where the driver has GL_EXT_shader_framebuffer_fetch (llvmpipe does) the composite reads the
// phantom from the target it draws; the images equal those that sample it as a texture, in all
// three composites, over several frames (the phantom attachment is never written).
TEST_F(FluoroRenderTest, ReadingThePhantomThroughTheFramebufferGivesTheSameImages) {
  FluoroRenderer sampled;
  const base::Status<> sampled_ready = sampled.init(false);
  ASSERT_TRUE(sampled_ready) << sampled_ready.error().message;
  EXPECT_FALSE(sampled.uses_framebuffer_fetch());
  sampled.set_vessel(neuro_->vessel);
  if (!renderer_.uses_framebuffer_fetch()) GTEST_SKIP() << "the driver has no GL_EXT_shader_framebuffer_fetch";
  const std::vector<float> filled = right_ica_filled(120);
  FluoroInputs dsa = live(81, filled, {wire_in_right_ica()});
  dsa.shown.mode = flow::ExposureMode::kSubtractionRun;
  dsa.image.run = 1;
  dsa.image.mask_pulse = 80;
  dsa.mask = {80, flow::ExposureMode::kFluoroscopy, no_contrast(), {}};
  FluoroInputs road = live(90, no_contrast(), {wire_in_right_ica()});
  road.image.roadmap_pulse = 81;
  road.roadmap = dsa.shown;
  road.roadmap_mask = dsa.mask;
  for (const FluoroInputs& in : {live(79, filled, {wire_in_right_ica()}), dsa, road, live(91, filled, {})}) {
    const Image fetched = render(in);
    EXPECT_EQ(sampled.render(Viewport{0, 0, kSize, kSize}, kSize, in), "");
    EXPECT_EQ(FrameCapture::read_back_buffer(kSize, kSize).pixels, fetched.pixels) << "pulse " << in.image.pulse;
  }
}

TEST_F(FluoroRenderTest, BadInputsAreOneLineAndABlackImage) {
  FluoroInputs in = live(3, no_contrast(), {wire_in_right_ica()});
  in.mask.cell_iodine_mgI_ml.assign(12, 0.0F);
  EXPECT_EQ(renderer_.render(Viewport{0, 0, kSize, kSize}, kSize, in),
            "FluoroInputs.mask.cell_iodine_mgI_ml: 12 cells, the vessel has " + std::to_string(neuro_->transport->cell_count()));
  const Image black = FrameCapture::read_back_buffer(kSize, kSize);
  EXPECT_EQ(*std::max_element(black.pixels.begin(), black.pixels.end()), 0);
  in = live(3, no_contrast(), {wire_in_right_ica()});
  in.shown.tools[0].radius_mm = 0.0F;
  EXPECT_EQ(renderer_.render(Viewport{0, 0, kSize, kSize}, kSize, in), "FluoroInputs.shown.tools[0].radius_mm: must be in (0, 10)");
  in = live(3, no_contrast(), {});
  in.shown.cell_iodine_mgI_ml[7] = -1.0F;
  EXPECT_EQ(renderer_.render(Viewport{0, 0, kSize, kSize}, kSize, in), "FluoroInputs.shown.cell_iodine_mgI_ml[7]: must be finite and >= 0");
  in = live(3, no_contrast(), {});
  in.pose.lao_deg = 200.0;
  EXPECT_EQ(renderer_.render(Viewport{0, 0, kSize, kSize}, kSize, in).rfind("FluoroInputs.pose: ", 0), 0U);
  EXPECT_EQ(renderer_.render(Viewport{0, 0, 0, 0}, kSize, live(3, no_contrast(), {})), "") << "an empty viewport draws nothing";
  in = live(3, no_contrast(), {});
  in.patient_transmission = 0.0;
  EXPECT_EQ(renderer_.render(Viewport{0, 0, kSize, kSize}, kSize, in), "FluoroInputs.patient_transmission: must be in (0, 1]");
}

TEST_F(FluoroRenderTest, VertexIodineFollowsTheTransportCells) {
  flow::ContrastTransport& t = *neuro_->transport;
  t.reset();
  ASSERT_TRUE(t.inject({neuro_->right_ica, 0.3 * t.locator().length_mm(neuro_->right_ica), 0.0}, {6.0, 3.0, 300.0}).empty());
  for (int i = 0; i < 100; ++i) t.step();
  const std::vector<float> c = cell_iodine(t);
  ASSERT_EQ(c.size(), t.cell_count());
  // A vertex's concentration equals the transport's on the centreline at its nearest point.
  const vessel::SurfaceMesh& mesh = neuro_->mesh;
  int checked = 0;
  for (std::size_t t_i = 0; t_i < mesh.triangle_count(); t_i += 97) {
    const vessel::FaceRegion r = mesh.triangle_regions[t_i];
    if (r.kind != vessel::RegionKind::kSegment) continue;
    const std::uint32_t v = mesh.triangles[3 * t_i];
    const flow::CenterlinePosition at = t.locate(glm::dvec3(mesh.positions_mm[v]));
    if (static_cast<std::int32_t>(neuro_->network->model().segments[at.segment].id) != r.id) continue;  // nearest is another segment
    EXPECT_NEAR(neuro_->vessel.concentration(v, c), t.concentration(at.segment, at.arc_mm), 1e-3 + 1e-3 * t.concentration(at.segment, at.arc_mm));
    ++checked;
  }
  EXPECT_GT(checked, 100);
  t.reset();
}

}  // namespace
}  // namespace cathbox::app::fluoro_test
