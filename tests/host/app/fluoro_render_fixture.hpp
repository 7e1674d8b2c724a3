#pragma once
// The fixture of the fluoroscopic view's tests under Xvfb (llvmpipe): one window and the bundled
// neuro case (its surface, flow network, contrast transport and the FluoroVessel drawn from
// them) for the whole executable, a fresh FluoroRenderer per test, and the helpers the tests
// measure images with (the C-arm's own projection, mean changes along projected points).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <glm/glm.hpp>

#include "app/fluoro_frontend.hpp"
#include "app/fluoro_renderer.hpp"
#include "app/frame_capture.hpp"
#include "app/gl_window.hpp"
#include "app/png_writer.hpp"
#include "flow/contrast_transport.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::app::fluoro_test {

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
  // the lumen chord, and a bolus front stays bounded (fluoro_attenuation_test.cpp).
  void expect_iodine_chords(const vessel::SurfaceMesh& mesh, const std::string& png);

  static GlWindow* window_;
  static Neuro* neuro_;
  FluoroRenderer renderer_;
};

// The distance of p from the polyline (pixels).
double distance_to_polyline(glm::dvec2 p, const std::vector<glm::dvec2>& line);

}  // namespace cathbox::app::fluoro_test
