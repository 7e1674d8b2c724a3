// Renders a fixture tube with a tool inside under Xvfb (llvmpipe) and checks, by projecting
// known 3D points with the same camera, that the pixels show the tool, the vessel, the target
// and the background where they should. Also round-trips the screenshot through the PNG writer.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include <glm/vec4.hpp>

#include "app/frame_capture.hpp"
#include "app/gl.hpp"
#include "app/gl_window.hpp"
#include "app/orbit_camera.hpp"
#include "app/png_writer.hpp"
#include "app/scene_renderer.hpp"
#include "png_reader.hpp"
#include "tube_fixture.hpp"

namespace cathbox::app {
namespace {

constexpr int kWidth = 640;
constexpr int kHeight = 400;

struct Rgb {
  int r, g, b;
};

Rgb at(const Image& img, const glm::vec2& px) {
  const std::uint8_t* p = img.pixel(static_cast<int>(px.x), static_cast<int>(px.y));
  return {p[0], p[1], p[2]};
}

glm::vec2 project(const glm::mat4& vp, const Viewport& view, const glm::vec3& p) {
  const glm::vec4 c = vp * glm::vec4(p, 1.0F);
  const float x = c.x / c.w;
  const float y = c.y / c.w;
  return {static_cast<float>(view.x) + (x * 0.5F + 0.5F) * static_cast<float>(view.width),
          static_cast<float>(view.y) + (0.5F - y * 0.5F) * static_cast<float>(view.height)};
}

bool is_tool(Rgb c) { return c.g > c.r + 40 && c.g > c.b + 40; }
bool is_vessel(Rgb c) { return c.r > c.g + 40 && c.r > c.b + 40; }
bool is_target(Rgb c) { return c.r > 150 && c.g > 100 && c.b < 90; }
bool is_background(Rgb c) {
  const glm::vec3 bg = 255.0F * SceneColors::kBackground;
  return std::abs(c.r - static_cast<int>(bg.r + 0.5F)) <= 2 &&
         std::abs(c.g - static_cast<int>(bg.g + 0.5F)) <= 2 &&
         std::abs(c.b - static_cast<int>(bg.b + 0.5F)) <= 2;
}

class RenderTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    base::Result<std::unique_ptr<GlWindow>> window = GlWindow::create(kWidth, kHeight, "cathbox render test", false);
    ASSERT_TRUE(window) << window.error().message;
    window_ = window->release();
  }
  static void TearDownTestSuite() { delete window_; }

  // A renderer showing a 100 mm fixture tube of radius 6 mm along X.
  void SetUp() override {
    ASSERT_NE(window_, nullptr);
    window_->framebuffer_size(fw_, fh_);
    ASSERT_EQ(fw_, kWidth);
    const base::Status<> renderer_ready = renderer_.init();
    ASSERT_TRUE(renderer_ready) << renderer_ready.error().message;
  }
  void use_tube(int rings, int sides) {
    const testing::FixtureMesh tube = testing::straight_tube(-50.0F, 50.0F, 6.0F, rings, sides);
    renderer_.set_vessel({tube.positions_mm, tube.normals, tube.triangles});
  }

  static GlWindow* window_;
  int fw_ = 0;
  int fh_ = 0;
  SceneRenderer renderer_;
};
GlWindow* RenderTest::window_ = nullptr;

SceneSnapshot tool_along_axis(float from_x, float to_x) {
  SceneSnapshot s;
  s.tool_count = 1;
  ToolView& t = s.tools[0];
  t.active = true;
  t.radius_mm = 0.3F;
  for (int i = 0; i <= 40; ++i) {
    t.nodes_mm.emplace_back(from_x + (to_x - from_x) * static_cast<float>(i) / 40.0F, 0.0F, 0.0F);
  }
  s.tip_mm = t.nodes_mm.back();
  s.tip_direction = glm::vec3(1, 0, 0);
  return s;
}

TEST_F(RenderTest, GlobalViewShowsToolInsideTranslucentVesselTargetAndBackground) {
  use_tube(41, 24);
  SceneRenderer& renderer = renderer_;
  const int fw = fw_;
  const int fh = fh_;
  std::string error;
  renderer.set_target(glm::vec3(40.0F, 0.0F, 0.0F), 2.0F);
  SceneSnapshot snap = tool_along_axis(-50.0F, 15.0F);
  snap.contacts.push_back({glm::vec3(-30.0F, 0.0F, -6.0F), 40.0F});  // on the wall, below the tool
  const RenderSettings settings;
  renderer.update_tools(snap, settings);

  OrbitCamera cam;
  cam.frame(glm::vec3(-50.0F, -6.0F, -6.0F), glm::vec3(50.0F, 6.0F, 6.0F));
  cam.pitch_rad = 0.3F;
  const Viewport view{0, 0, fw, fh};
  renderer.clear(fw, fh);
  renderer.render_global(view, fh, cam.view(), cam.projection(view.aspect()), settings);
  const Image shot = FrameCapture::read_back_buffer(fw, fh);

  // Round trip through the PNG writer, as the trainer's --screenshot does.
  const std::string path = std::string(CATHBOX_TEST_OUT) + "/render_test_global.png";
  const base::Status<> written = PngWriter::write_file(path, shot);
  ASSERT_TRUE(written) << written.error().message;
  const auto img = testing::read_png(path, error);
  ASSERT_TRUE(img) << error;
  ASSERT_EQ(img->pixels, shot.pixels);

  const glm::mat4 vp = cam.projection(view.aspect()) * cam.view();
  for (float x : {-40.0F, -20.0F, 0.0F, 10.0F}) {
    const Rgb c = at(*img, project(vp, view, glm::vec3(x, 0.0F, 0.0F)));
    EXPECT_TRUE(is_tool(c)) << "tool at x=" << x << ": " << c.r << "," << c.g << "," << c.b;
  }
  for (float x : {25.0F, 30.0F}) {
    const Rgb c = at(*img, project(vp, view, glm::vec3(x, 0.0F, 0.0F)));
    EXPECT_TRUE(is_vessel(c)) << "vessel at x=" << x << ": " << c.r << "," << c.g << "," << c.b;
  }
  // Off the axis but inside the tube: vessel, not tool.
  const Rgb wall = at(*img, project(vp, view, glm::vec3(-20.0F, 0.0F, 4.0F)));
  EXPECT_TRUE(is_vessel(wall)) << wall.r << "," << wall.g << "," << wall.b;
  const Rgb contact = at(*img, project(vp, view, glm::vec3(-30.0F, 0.0F, -6.0F)));
  EXPECT_TRUE(contact.r > 150 && contact.g > 50 && contact.g < contact.r - 60 && contact.b < 60)
      << "contact marker: " << contact.r << "," << contact.g << "," << contact.b;
  const Rgb target = at(*img, project(vp, view, glm::vec3(40.0F, 0.0F, 0.0F)));
  EXPECT_TRUE(is_target(target)) << target.r << "," << target.g << "," << target.b;
  for (const glm::vec3& p : {glm::vec3(0, 0, 25), glm::vec3(0, 0, -25), glm::vec3(-60, 0, 15)}) {
    const glm::vec2 px = project(vp, view, p);
    ASSERT_TRUE(view.contains(px.x, px.y));
    const Rgb c = at(*img, px);
    EXPECT_TRUE(is_background(c)) << c.r << "," << c.g << "," << c.b;
  }
}

TEST_F(RenderTest, WireframeLeavesGapsBetweenEdges) {
  use_tube(11, 12);
  SceneRenderer& renderer = renderer_;
  const int fw = fw_;
  const int fh = fh_;
  OrbitCamera cam;
  cam.frame(glm::vec3(-50.0F, -6.0F, -6.0F), glm::vec3(50.0F, 6.0F, 6.0F));
  RenderSettings settings;
  const Viewport view{0, 0, fw, fh};
  auto count_vessel = [&](bool wireframe) {
    settings.wireframe = wireframe;
    renderer.clear(fw, fh);
    renderer.render_global(view, fh, cam.view(), cam.projection(view.aspect()), settings);
    const Image img = FrameCapture::read_back_buffer(fw, fh);
    int n = 0;
    for (int y = 0; y < fh; ++y)
      for (int x = 0; x < fw; ++x) n += is_background(at(img, glm::vec2(x, y))) ? 0 : 1;
    return n;
  };
  const int surface = count_vessel(false);
  const int wire = count_vessel(true);
  EXPECT_GT(surface, fw * fh / 20);
  EXPECT_GT(wire, 0);
  EXPECT_LT(wire, surface / 2);
}

TEST_F(RenderTest, LocalViewFromTheTipSeesTheLumenAndNotTheBackground) {
  use_tube(41, 24);
  SceneRenderer& renderer = renderer_;
  const int fw = fw_;
  const int fh = fh_;
  const SceneSnapshot snap = tool_along_axis(-50.0F, -10.0F);
  renderer.update_tools(snap, RenderSettings{});
  const Viewport local{fw / 2, 0, fw / 2, fh / 2};
  renderer.clear(fw, fh);
  renderer.render_local(local, fh, snap);
  const Image img = FrameCapture::read_back_buffer(fw, fh);
  const base::Status<> written = PngWriter::write_file(std::string(CATHBOX_TEST_OUT) + "/render_test_local.png", img);
  ASSERT_TRUE(written) << written.error().message;
  // Inside the tube every pixel of the local view is wall (lit or fogged), none background;
  // the wall near the edge of the view is closer, so brighter than the far centre.
  int background = 0;
  for (int y = local.y; y < local.y + local.height; ++y)
    for (int x = local.x; x < local.x + local.width; ++x)
      background += is_background(at(img, glm::vec2(x, y))) ? 1 : 0;
  EXPECT_EQ(background, 0);
  const Rgb centre = at(img, glm::vec2(local.x + local.width / 2, local.y + local.height / 2));
  const Rgb edge = at(img, glm::vec2(local.x + 2, local.y + local.height / 2));
  EXPECT_GT(edge.r, centre.r + 30) << edge.r << " vs " << centre.r;
  // The rest of the window is untouched by the local view.
  EXPECT_TRUE(is_background(at(img, glm::vec2(10, 10))));
}

}  // namespace
}  // namespace cathbox::app
