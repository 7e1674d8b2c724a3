// The fluoroscopic view (FluoroRenderer) under Xvfb (llvmpipe) on the bundled neuro case, fed
// by sim/flow objects driven here directly: a FlowNetwork and a ContrastTransport with an
// injection in the right internal carotid, the C-arm of c_arm.hpp, and a guidewire laid along
// the right ICA. Positions are checked against the C-arm's own projection (CArm::project_px);
// comparisons of two renders differ only in what is tested (noise off, or the same pulse).
// Screenshots: fluoro_*.png in the build folder of this test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <glm/geometric.hpp>

#include "app/fluoro_frontend.hpp"
#include "app/fluoro_renderer.hpp"
#include "app/frame_capture.hpp"
#include "app/gl_window.hpp"
#include "app/png_writer.hpp"
#include "flow/contrast_transport.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::app {
namespace {

constexpr int kSize = 512;

struct Neuro {
  vessel::VesselModel model;
  vessel::SurfaceMesh mesh;
  std::unique_ptr<flow::FlowNetwork> network;
  std::unique_ptr<flow::ContrastTransport> transport;
  FluoroVessel vessel;
  std::uint32_t right_ica = 0;
  std::uint32_t left_ica = 0;
};

class FluoroRenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    base::Result<std::unique_ptr<GlWindow>> window = GlWindow::create(kSize, kSize, "cathbox fluoro test", false);
    ASSERT_TRUE(window) << window.error().message;
    window_ = window->release();
    neuro_ = new Neuro;
    const vessel::HclmReadResult read = vessel::load_hclm(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.hclm");
    ASSERT_TRUE(read.ok());
    neuro_->model = read.model;
    vessel::VesselSurface surface = vessel::build_vessel_surface(neuro_->model);
    ASSERT_TRUE(surface.ok()) << surface.error;
    neuro_->mesh = std::move(surface.mesh);
    flow::FlowBuild built = flow::FlowNetwork::build(neuro_->model);
    ASSERT_TRUE(built);
    neuro_->network = std::move(*built);
    neuro_->transport = std::make_unique<flow::ContrastTransport>(*neuro_->network);
    const vessel::VesselModel& m = neuro_->network->model();
    for (std::uint32_t i = 0; i < m.segments.size(); ++i) {
      if (m.segments[i].name == "right_internal_carotid") neuro_->right_ica = i;
      if (m.segments[i].name == "left_internal_carotid") neuro_->left_ica = i;
    }
    neuro_->vessel = FluoroVessel::build(neuro_->mesh, *neuro_->transport);
  }
  static void TearDownTestSuite() {
    delete neuro_;
    delete window_;
  }
  void SetUp() override {
    ASSERT_NE(window_, nullptr);
    const base::Status<> renderer_ready = renderer_.init();
    ASSERT_TRUE(renderer_ready) << renderer_ready.error().message;
    renderer_.set_vessel(neuro_->vessel);
  }

  Image render(const FluoroInputs& in) {
    EXPECT_EQ(renderer_.render(Viewport{0, 0, kSize, kSize}, kSize, in), "");
    return FrameCapture::read_back_buffer(kSize, kSize);
  }
  static void save(const Image& img, const std::string& name) {
    const base::Status<> written = PngWriter::write_file(std::string(CATHBOX_TEST_OUT) + "/" + name, img);
    EXPECT_TRUE(written) << written.error().message;
  }

  // Live fluoroscopy showing pulse `pulse` with the given iodine and tools.
  static FluoroInputs live(std::int64_t pulse, std::vector<float> iodine, std::vector<FluoroTool> tools,
                           const flow::CArmPose& pose = {}) {
    FluoroInputs in;
    in.pose = pose;
    in.patient_transmission = flow::HeadPhantom::neuro().central_transmission(flow::CArm(pose));
    in.image.pulse = pulse;
    in.image.beam_on = true;
    in.shown = {pulse, flow::ExposureMode::kFluoroscopy, std::move(iodine), std::move(tools)};
    return in;
  }
  static std::vector<float> no_contrast() { return std::vector<float>(neuro_->transport->cell_count(), 0.0F); }
  // The cells' iodine `steps` transport steps after 6 mL at 3 mL/s into the right ICA (then reset).
  static std::vector<float> right_ica_filled(int steps) {
    flow::ContrastTransport& t = *neuro_->transport;
    t.reset();
    EXPECT_TRUE(t.inject({neuro_->right_ica, 0.3 * t.locator().length_mm(neuro_->right_ica), 0.0}, {6.0, 3.0, 300.0}).empty());
    for (int i = 0; i < steps; ++i) t.step();
    std::vector<float> c = cell_iodine(t);
    t.reset();
    return c;
  }
  // Centreline points of a segment between two fractions of its length.
  static std::vector<glm::vec3> centreline(std::uint32_t segment, double from, double to, int n) {
    const flow::CenterlineLocator& loc = neuro_->transport->locator();
    std::vector<glm::vec3> out;
    for (int i = 0; i <= n; ++i) {
      const double f = from + (to - from) * i / n;
      out.emplace_back(loc.point_at(segment, f * loc.length_mm(segment)));
    }
    return out;
  }
  static FluoroTool wire_in_right_ica() {
    FluoroTool t;
    t.nodes_mm = centreline(neuro_->right_ica, 0.05, 0.6, 60);
    t.radius_mm = 0.18F;
    t.markers.push_back({0.0, 3.0, flow::XrayMaterial::kPlatinum});  // a 3 mm platinum tip
    return t;
  }
  static int grey(const Image& img, glm::dvec2 px) {
    return img.pixel(static_cast<int>(px.x), static_cast<int>(px.y))[0];
  }
  // Mean of (b - a) over the pixels at the projected points.
  static double mean_change(const Image& a, const Image& b, const flow::CArm& carm, const std::vector<glm::vec3>& pts) {
    double s = 0.0;
    int n = 0;
    for (const glm::dvec2& px : in_image(carm, pts)) {
      s += grey(b, px) - grey(a, px);
      ++n;
    }
    EXPECT_GT(n, static_cast<int>(pts.size()) / 3) << "most points in the image";
    return n > 0 ? s / n : 0.0;
  }
  // The root mean square of b - a (grey) over the image's central half.
  static double rms_difference(const Image& a, const Image& b) {
    double s = 0.0;
    int n = 0;
    for (int y = kSize / 4; y < 3 * kSize / 4; ++y) {
      for (int x = kSize / 4; x < 3 * kSize / 4; ++x) {
        const double d = b.pixel(x, y)[0] - a.pixel(x, y)[0];
        s += d * d;
        ++n;
      }
    }
    return std::sqrt(s / n);
  }
  // The projections of the points that fall inside the image (4 px from its edges).
  static std::vector<glm::dvec2> in_image(const flow::CArm& carm, const std::vector<glm::vec3>& pts) {
    std::vector<glm::dvec2> out;
    for (const glm::vec3& p : pts) {
      const glm::dvec2 px = carm.project_px(glm::dvec3(p), kSize, kSize);
      if (px.x >= 4.0 && px.y >= 4.0 && px.x < kSize - 4.0 && px.y < kSize - 4.0) out.push_back(px);
    }
    return out;
  }

  // Iodine in the right ICA drawn on `mesh` (set in renderer_): the subtraction shows mu times
  // the lumen chord, and a bolus front stays bounded (the test below says why).
  void expect_iodine_chords(const vessel::SurfaceMesh& mesh, const std::string& png) {
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

  static GlWindow* window_;
  static Neuro* neuro_;
  FluoroRenderer renderer_;
};
GlWindow* FluoroRenderTest::window_ = nullptr;
Neuro* FluoroRenderTest::neuro_ = nullptr;

double distance_to_polyline(glm::dvec2 p, const std::vector<glm::dvec2>& line) {
  double best = 1e30;
  for (std::size_t i = 0; i + 1 < line.size(); ++i) {
    const glm::dvec2 ab = line[i + 1] - line[i];
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - line[i], ab) / len2, 0.0, 1.0) : 0.0;
    best = std::min(best, glm::length(line[i] + t * ab - p));
  }
  return best;
}

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
}  // namespace cathbox::app
