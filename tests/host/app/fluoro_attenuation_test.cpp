// The fluoroscopic view's figures against Beer-Lambert, under Xvfb (llvmpipe) on the bundled
// neuro case (fluoro_render_fixture.hpp): a soft-tissue rod and iodine in the lumen show mu
// times their chords (on the trainer's surface and on the coarser fluoroscopy one), and the
// quantum noise is deterministic per pulse and falls with the dose.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <span>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

#include "fluoro_render_fixture.hpp"

namespace cathbox::app::fluoro_test {

// Iodine in the right ICA drawn on `mesh` (set in renderer_): the subtraction shows mu times the
// lumen chord, and a bolus front stays bounded (the test below says why).
void FluoroRenderTest::expect_iodine_chords(const vessel::SurfaceMesh& mesh, const std::string& png) {
  renderer_.set_display({.noise = false});
  const flow::CArm carm{flow::CArmPose{}};
  const FluoroDisplay display;
  const flow::ContrastTransport& t = *neuro_->transport;
  const double mu = 100.0 * flow::iodine_per_mm_per_mgI_ml();
  const auto subtracted = [&](std::vector<float> iodine) {
    FluoroInputs dsa = live(51, std::move(iodine), {});
    dsa.shown.mode = flow::ExposureMode::kSubtractionRun;
    dsa.image.run = 1;
    dsa.image.mask_pulse = 50;
    dsa.mask = {50, flow::ExposureMode::kFluoroscopy, no_contrast(), {}};
    return render(dsa);
  };
  const auto delta_L = [&](const Image& img, glm::dvec2 px) {
    return (255.0 * display.dsa_background - img.pixel(static_cast<int>(px.x), static_cast<int>(px.y))[0]) / (255.0 * display.dsa_gain);
  };
  const std::uint32_t ica = neuro_->right_ica;
  const std::span<const double> cells = t.cell_concentrations(ica);
  const auto first = static_cast<std::size_t>(cells.data() - t.cell_concentrations(0).data());
  std::vector<float> filled = no_contrast();  // the right ICA only, so no other vessel overlaps it
  for (std::size_t i = 0; i < cells.size(); ++i) filled[first + i] = 100.0F;
  const Image full = subtracted(filled);
  // Only the triangles reading a filled cell are drawn: the right ICA's, a small part of the tree.
  EXPECT_GT(renderer_.last_work().vessel_triangles, 0U);
  EXPECT_LT(renderer_.last_work().vessel_triangles, mesh.triangle_count() / 4);
  const double length = t.locator().length_mm(ica);
  int checked = 0;
  for (double f = 0.3; f <= 0.8; f += 0.02) {
    const glm::dvec3 p = t.locator().point_at(ica, f * length);
    const glm::dvec3 axis = glm::normalize(t.locator().point_at(ica, f * length + 2.0) - t.locator().point_at(ica, f * length - 2.0));
    const glm::dvec3 ray = glm::normalize(p - carm.source_mm());
    const double chord = 2.0 * t.locator().radius_at(ica, f * length) / std::sqrt(1.0 - std::pow(glm::dot(axis, ray), 2.0));
    EXPECT_NEAR(delta_L(full, carm.project_px(p, kSize, kSize)), mu * chord, 0.12 * mu * chord) << "at " << f << " of the right ICA";
    ++checked;
  }
  EXPECT_GE(checked, 25);
  // A bolus front: the right ICA's first cells filled, the rest empty.
  std::vector<float> front = no_contrast();
  for (std::size_t i = 0; i < cells.size() / 2; ++i) front[first + i] = 100.0F;
  const Image bolus = subtracted(front);
  double max_chord = 0.0;
  for (double f = 0.0; f <= 1.0; f += 0.01) max_chord = std::max(max_chord, 2.0 * t.locator().radius_at(ica, f * length));
  for (int y = 0; y < kSize; ++y) {
    for (int x = 0; x < kSize; ++x) {
      const double d = delta_L(bolus, {x + 0.5, y + 0.5});
      ASSERT_GT(d, -0.01) << x << "," << y;
      ASSERT_LT(d, 3.0 * mu * max_chord) << x << "," << y;  // a foreshortened piece may be long, not unbounded
    }
  }
  save(subtracted(front), png);
}

namespace {

// Beer-Lambert, quantitatively: a 6 mm soft-tissue rod across the beam at the isocentre,
// subtracted from a mask without it, shows mu * chord: 2 r mu through its axis, and it is as
// wide as the C-arm magnifies it.
TEST_F(FluoroRenderTest, ASubtractedRodShowsMuTimesItsChord) {
  renderer_.set_display({.noise = false});
  const flow::CArm carm{flow::CArmPose{}};
  const glm::vec3 iso(carm.isocenter_mm());
  FluoroTool rod;
  rod.radius_mm = 3.0F;
  rod.material = flow::XrayMaterial::kSoftTissue;
  for (int i = 0; i <= 8; ++i) rod.nodes_mm.push_back(iso + glm::vec3(-20.0F + 5.0F * static_cast<float>(i), 0.0F, 0.0F));
  FluoroInputs dsa = live(41, no_contrast(), {rod});
  dsa.shown.mode = flow::ExposureMode::kSubtractionRun;
  dsa.image.run = 1;
  dsa.image.mask_pulse = 40;
  dsa.mask = {40, flow::ExposureMode::kFluoroscopy, no_contrast(), {}};
  const Image img = render(dsa);
  const FluoroDisplay display;
  const glm::dvec2 c = carm.project_px(carm.isocenter_mm(), kSize, kSize);
  // The subtraction's background, as stored (8 bits) away from the rod and as computed.
  EXPECT_NEAR(img.pixel(static_cast<int>(c.x), static_cast<int>(c.y) + 60)[0], 255.0 * display.dsa_background, 0.51);
  const double background = 255.0 * display.dsa_background;
  const auto delta_L = [&](int x, int y) { return (background - img.pixel(x, y)[0]) / (255.0 * display.dsa_gain); };
  const double mu = flow::linear_attenuation_per_mm(flow::XrayMaterial::kSoftTissue);
  // Across the rod, the integral of mu * chord is mu times its cross-section: the tube is an
  // octagon of circumradius r (area 2 sqrt(2) r^2), each pixel patient_pixel_mm wide.
  const double patient_pixel_mm = carm.pixel_mm(kSize, kSize) / carm.magnification(carm.isocenter_mm());
  double integral = 0.0;
  int wide = 0;
  for (int y = static_cast<int>(c.y) - 12; y <= static_cast<int>(c.y) + 12; ++y) {  // the rod is ~19 px wide
    const double d = delta_L(static_cast<int>(c.x), y);
    integral += d * patient_pixel_mm;
    wide += d > 0.1 * mu ? 1 : 0;
  }
  EXPECT_NEAR(integral, mu * 2.0 * std::sqrt(2.0) * 9.0, 0.02 * mu * 2.0 * std::sqrt(2.0) * 9.0);
  // Through the axis about mu * 2 r (the pixel centre passes within half a pixel of it).
  EXPECT_NEAR(delta_L(static_cast<int>(c.x), static_cast<int>(c.y)), 2.0 * 3.0 * mu, 0.05 * 2.0 * 3.0 * mu);
  // Its width: 2 r times the magnification, in pixels.
  EXPECT_NEAR(wide, 6.0 / patient_pixel_mm, 2.0);
  // Beyond its ends, nothing.
  const glm::dvec2 beyond = carm.project_px(glm::dvec3(iso + glm::vec3(30.0F, 0.0F, 0.0F)), kSize, kSize);
  EXPECT_NEAR(delta_L(static_cast<int>(beyond.x), static_cast<int>(beyond.y)), 0.0, 0.004);
}

// Iodine in the lumen: with 100 mgI/mL in the right ICA the subtraction along it shows
// mu_I c times the chord through its axis, 2 r / sqrt(1 - (axis . beam)^2); with a step in the
// concentration (the first half of the right ICA's cells filled, a bolus front) nothing
// overshoots or goes negative: the trapezoid correction for mu differing between entry and exit.
TEST_F(FluoroRenderTest, IodineShowsMuTimesTheLumenChordAndABolusFrontStaysBounded) {
  expect_iodine_chords(neuro_->mesh, "fluoro_bolus_front_dsa.png");
}

TEST_F(FluoroRenderTest, OnTheCoarserFluoroSurfaceIodineShowsTheSameChords) {
  const vessel::VesselSurface coarse = vessel::build_vessel_surface(neuro_->model, fluoro_surface_options());
  ASSERT_TRUE(coarse.ok()) << coarse.error;
  EXPECT_LT(coarse.mesh.triangle_count(), neuro_->mesh.triangle_count() / 3);
  renderer_.set_vessel(FluoroVessel::build(coarse.mesh, *neuro_->transport));
  expect_iodine_chords(coarse.mesh, "fluoro_bolus_front_dsa_fluoro_surface.png");
}

TEST_F(FluoroRenderTest, NoiseIsDeterministicPerPulseAndFallsWithTheDose) {
  const Image a = render(live(7, no_contrast(), {}));
  const Image b = render(live(7, no_contrast(), {}));
  EXPECT_EQ(a.pixels, b.pixels);
  EXPECT_EQ(renderer_.last_work().scenes_accumulated, 0) << "same inputs: nothing accumulated again";
  EXPECT_EQ(renderer_.last_work().composites, 0) << "nor composed: the image is copied";
  const Image c = render(live(8, no_contrast(), {}));
  EXPECT_NE(a.pixels, c.pixels);
  // Last-image hold draws the held pulse: the same picture as when it was live.
  FluoroInputs held = live(7, no_contrast(), {});
  held.image.beam_on = false;
  EXPECT_EQ(render(held).pixels, a.pixels);
  // Without the image cache (another renderer, made fresh) the same pulse gives the same image.
  FluoroRenderer fresh;
  const base::Status<> fresh_ready = fresh.init();
  ASSERT_TRUE(fresh_ready) << fresh_ready.error().message;
  fresh.set_vessel(neuro_->vessel);
  EXPECT_EQ(fresh.render(Viewport{0, 0, kSize, kSize}, kSize, held), "");
  EXPECT_EQ(FrameCapture::read_back_buffer(kSize, kSize).pixels, a.pixels);
  // A subtraction-run frame (25x the dose of a fluoroscopy pulse) is less noisy than fluoroscopy.
  renderer_.set_display({.noise = false});
  const Image clean = render(live(7, no_contrast(), {}));
  renderer_.set_display({});
  FluoroInputs run = live(7, no_contrast(), {});
  run.shown.mode = flow::ExposureMode::kSubtractionRun;
  const Image run_img = render(run);
  const auto rms = [&](const Image& img) { return rms_difference(img, clean); };
  // sigma: fluoroscopy 0.38 (temporal filter) / sqrt(40 nGy), a run frame 1 / sqrt(1000 nGy): 1.9x.
  EXPECT_GT(rms(a), 1.5 * rms(run_img));
  EXPECT_GT(rms(a), 1.0);
  // Before the first pulse the monitor is black.
  FluoroInputs none;
  const Image black = render(none);
  EXPECT_EQ(*std::max_element(black.pixels.begin(), black.pixels.end()), 0);
}

}  // namespace
}  // namespace cathbox::app::fluoro_test
