// The trainer's headless test mode: runs `cathbox-trainer --headless --frames N --screenshot`
// under Xvfb (Mesa llvmpipe) on the default case with the scripted hand, then checks the
// screenshot against the camera the trainer wrote beside it: the vessel's centerline (read
// here from the case's HCLM file by the vessel module, independently of the trainer) projects
// onto vessel-coloured pixels, the tool's nodes onto tool-coloured pixels and lie inside the
// vessel, the corners of the global view show the background and the local view shows the
// lumen.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/gtc/type_ptr.hpp>
#include <glm/mat4x4.hpp>
#include <glm/vec4.hpp>

#include "app/scene_renderer.hpp"
#include "flow/c_arm.hpp"
#include "scenario/case_file.hpp"
#include "app/viewport.hpp"
#include "png_reader.hpp"
#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

namespace cathbox::app {
namespace {

struct Sidecar {
  int width = 0;
  int height = 0;
  std::string vessel_file;
  Viewport global;
  Viewport local;
  Viewport hud;
  glm::mat4 view{1.0F};
  glm::mat4 proj{1.0F};
  std::vector<glm::vec3> nodes;
  glm::vec3 tip{0.0F};
  glm::vec3 target{0.0F};
  std::int64_t sim_time_us = 0;
};

bool read_sidecar(const std::string& path, Sidecar& s) {
  std::ifstream in(path);
  std::string line;
  auto rect = [](std::istringstream& ls, Viewport& v) { ls >> v.x >> v.y >> v.width >> v.height; };
  auto matrix = [](std::istringstream& ls, glm::mat4& m) {
    float* p = glm::value_ptr(m);
    for (int i = 0; i < 16; ++i) ls >> p[i];
  };
  while (std::getline(in, line)) {
    std::istringstream ls(line);
    std::string key;
    ls >> key;
    if (key == "size") ls >> s.width >> s.height;
    else if (key == "vessel_file") ls >> s.vessel_file;
    else if (key == "global") rect(ls, s.global);
    else if (key == "local") rect(ls, s.local);
    else if (key == "hud") rect(ls, s.hud);
    else if (key == "view") matrix(ls, s.view);
    else if (key == "proj") matrix(ls, s.proj);
    else if (key == "node") {
      int tool = 0;
      glm::vec3 p;
      ls >> tool >> p.x >> p.y >> p.z;
      s.nodes.push_back(p);
    } else if (key == "tip") ls >> s.tip.x >> s.tip.y >> s.tip.z;
    else if (key == "sim_time_us") ls >> s.sim_time_us;
    else if (key == "target") ls >> s.target.x >> s.target.y >> s.target.z;
  }
  return s.width > 0 && !s.vessel_file.empty();
}

struct Rgb {
  int r, g, b;
};

class TrainerScreenshot : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    shot_ = std::string(CATHBOX_TEST_OUT) + "/trainer_screenshot.png";
    std::remove(shot_.c_str());
    const std::string cmd = std::string(CATHBOX_XVFB_RUN) + " -a -s '-screen 0 1280x800x24' " +
                            CATHBOX_TRAINER + " --headless --no-record --frames 40 --ms-per-frame 50 --size 1280x720 --screenshot " +
                            shot_ + " > " + shot_ + ".log 2>&1";
    status_ = std::system(cmd.c_str());
  }
  static std::string shot_;
  static int status_;

  static glm::vec2 project(const Sidecar& s, const glm::vec3& p, bool* in_front) {
    const glm::vec4 c = s.proj * s.view * glm::vec4(p, 1.0F);
    *in_front = c.w > 0.0F;
    return {static_cast<float>(s.global.x) + (c.x / c.w * 0.5F + 0.5F) * static_cast<float>(s.global.width),
            static_cast<float>(s.global.y) + (0.5F - c.y / c.w * 0.5F) * static_cast<float>(s.global.height)};
  }
  // Inside the global view by a margin and away from the HUD panel.
  static bool usable(const Sidecar& s, const glm::vec2& px) {
    const Viewport inner{s.global.x + 3, s.global.y + 3, s.global.width - 6, s.global.height - 6};
    const Viewport hud{s.hud.x - 3, s.hud.y - 3, s.hud.width + 6, s.hud.height + 6};
    return inner.contains(px.x, px.y) && !hud.contains(px.x, px.y);
  }
  static Rgb at(const Image& img, const glm::vec2& px) {
    const std::uint8_t* p = img.pixel(static_cast<int>(px.x), static_cast<int>(px.y));
    return {p[0], p[1], p[2]};
  }
};
std::string TrainerScreenshot::shot_;
int TrainerScreenshot::status_ = -1;

TEST_F(TrainerScreenshot, ShowsTheVesselAndTheToolWhereTheyShouldBe) {
  ASSERT_EQ(status_, 0) << "see " << shot_ << ".log";
  std::string error;
  const auto img = testing::read_png(shot_, error);
  ASSERT_TRUE(img) << error;
  Sidecar s;
  ASSERT_TRUE(read_sidecar(shot_ + ".txt", s));
  ASSERT_EQ(img->width, 1280);
  ASSERT_EQ(img->height, 720);
  EXPECT_EQ(s.sim_time_us, 40 * 50 * 1000);  // 40 frames of 50 ms of virtual time

  // The tool: inserted, inside the vessel, and drawn where its nodes project.
  const vessel::VesselSurface surface = vessel::load_vessel_surface(s.vessel_file);
  ASSERT_TRUE(surface.ok()) << surface.error;
  std::vector<std::pair<glm::vec3, float>> axis;
  for (const vessel::Segment& seg : surface.smoothed.segments) {
    for (const vessel::CenterlinePoint& p : seg.points) axis.emplace_back(glm::vec3(p.pos_mm), static_cast<float>(p.radius_mm));
  }
  // How far a point is outside the lumen: the smallest (distance to a centreline piece minus the
  // radius there, interpolated along the piece), over every piece of every segment.
  const auto outside_mm = [&surface](const glm::vec3& x) {
    float best = 1e9F;
    for (const vessel::Segment& seg : surface.smoothed.segments) {
      for (std::size_t i = 0; i + 1 < seg.points.size(); ++i) {
        const glm::vec3 a(seg.points[i].pos_mm);
        const glm::vec3 b(seg.points[i + 1].pos_mm);
        const glm::vec3 ab = b - a;
        const float len2 = glm::dot(ab, ab);
        const float t = len2 > 0.0F ? std::clamp(glm::dot(x - a, ab) / len2, 0.0F, 1.0F) : 0.0F;
        const float r = static_cast<float>(seg.points[i].radius_mm) * (1.0F - t) + static_cast<float>(seg.points[i + 1].radius_mm) * t;
        best = std::min(best, glm::distance(x, a + t * ab) - r);
      }
    }
    return best;
  };
  ASSERT_GE(s.nodes.size(), 5U);
  // Margins, from what the renderer and the solver achieve on this case (measured: every node's
  // surface inside the lumen, 40 of 41 probed nodes on tool pixels, 800 of 805 centreline
  // points on vessel pixels, the whole local view reddish):
  //   - a node's surface (0.18 mm wire) at most 10% of its radius past the wall (the solver's
  //     own penetration bound in the stability test);
  //   - >= 95% of the probed tool nodes on tool pixels (a node hidden behind a nearer wall
  //     fold of the translucent vessel may take its colour);
  //   - >= 98% of the unobstructed centreline points on vessel pixels; >= 99% reddish local view.
  constexpr float kToolRadius_mm = 0.18F;
  int tool_seen = 0;
  int tool_probed = 0;
  for (const glm::vec3& n : s.nodes) {
    EXPECT_LT(outside_mm(n) + kToolRadius_mm, 0.1F * kToolRadius_mm) << "tool node outside the vessel";
    bool front = false;
    const glm::vec2 px = project(s, n, &front);
    if (!front || !usable(s, px)) continue;
    ++tool_probed;
    const Rgb c = at(*img, px);
    tool_seen += (c.g > c.r + 30 && c.g > c.b + 30) ? 1 : 0;
  }
  ASSERT_GE(tool_probed, 5);
  EXPECT_GE(tool_seen * 100, tool_probed * 95) << tool_seen << " of " << tool_probed << " tool nodes";

  // The vessel: centerline points away from the tool show vessel colour.
  int vessel_seen = 0;
  int vessel_probed = 0;
  for (const auto& [c, r] : axis) {
    bool near_tool = false;
    for (const glm::vec3& n : s.nodes) near_tool = near_tool || glm::distance(n, c) < r + 3.0F;
    bool front = false;
    const glm::vec2 px = project(s, c, &front);
    if (near_tool || !front || !usable(s, px)) continue;
    ++vessel_probed;
    const Rgb p = at(*img, px);
    vessel_seen += (p.r > p.g + 25 && p.r > p.b + 25) ? 1 : 0;
  }
  ASSERT_GE(vessel_probed, 50);
  EXPECT_GE(vessel_seen * 100, vessel_probed * 98) << vessel_seen << " of " << vessel_probed;

  // Background in the lower corners of the global view.
  const glm::vec3 bg = 255.0F * SceneColors::kBackground;
  for (const glm::vec2 px : {glm::vec2(s.global.x + 4, s.global.y + s.global.height - 5),
                             glm::vec2(s.global.x + s.global.width - 5, s.global.y + s.global.height - 5)}) {
    const Rgb p = at(*img, px);
    EXPECT_NEAR(p.r, bg.r, 3.0F);
    EXPECT_NEAR(p.g, bg.g, 3.0F);
    EXPECT_NEAR(p.b, bg.b, 3.0F);
  }

  // The local view is inside the lumen: reddish wall or fog everywhere, never the background.
  int reddish = 0;
  int total = 0;
  for (int y = s.local.y + 2; y < s.local.y + s.local.height - 2; y += 7) {
    for (int x = s.local.x + 2; x < s.local.x + s.local.width - 2; x += 7) {
      const Rgb p = at(*img, glm::vec2(x, y));
      ++total;
      reddish += p.r > p.b ? 1 : 0;
    }
  }
  EXPECT_GE(reddish * 100, total * 99) << reddish << " of " << total;
}

}  // namespace
}  // namespace cathbox::app

namespace cathbox::app {
namespace {

std::string read_text(const std::string& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The trainer with `args`; its stdout (stderr goes beside it), empty when it failed.
std::string run_trainer(const std::string& args, const std::string& out) {
  const std::string cmd = std::string(CATHBOX_TRAINER) + " " + args + " > " + out + " 2> " + out + ".err";
  if (std::system(cmd.c_str()) != 0) return {};
  return read_text(out);
}

std::size_t count_of(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::string only_record_in(const std::string& dir) {
  std::string found;
  for (const auto& e : std::filesystem::directory_iterator(dir)) {
    if (e.path().extension() == ".cbxrec") found = found.empty() ? e.path().string() : "more than one";
  }
  return found;
}

// The trainer headless under Xvfb in the fluoroscopic view (`args`: case, frames, ...): its
// screenshot, the sidecar and the HUD's rectangle with a margin; false when any is missing.
struct FluoroShot {
  std::optional<Image> img;
  Sidecar s;
  Viewport hud;
};
bool take_fluoro_shot(const std::string& args, const std::string& shot, FluoroShot& out) {
  std::remove(shot.c_str());
  const std::string cmd = std::string(CATHBOX_XVFB_RUN) + " -a -s '-screen 0 1280x800x24' " + CATHBOX_TRAINER +
                          " --headless --no-record --view fluoro --size 1280x720 " + args + " --screenshot " + shot +
                          " > " + shot + ".log 2>&1";
  if (std::system(cmd.c_str()) != 0) return false;
  std::string error;
  out.img = testing::read_png(shot, error);
  if (!out.img || !read_sidecar(shot + ".txt", out.s)) return false;
  out.hud = Viewport{out.s.hud.x - 3, out.s.hud.y - 3, out.s.hud.width + 6, out.s.hud.height + 6};
  return true;
}

// The case's first working projection with the isocentre on `target`, as the trainer starts.
flow::CArm first_view_carm(const tool::Case& c, const glm::vec3& target) {
  flow::CArmPose pose;
  pose.lao_deg = c.views.front().lao_deg;
  pose.cranial_deg = c.views.front().cranial_deg;
  pose.isocenter_mm = glm::dvec3(target);
  return flow::CArm(pose);
}

// Without a display: the default case run by the scripted hand in virtual time until the tip
// reaches the case's target, the end-of-run summary on stdout, the same output on every run;
// the run is recorded, and the record replays (hash-checked) to the same figures.
// --view fluoro: the main view is the fluoroscopic image (grey) in the case's first working
// projection with the isocentre on the target, and the wire's platinum tip is dark where that
// C-arm projects it.
TEST(TrainerFluoroView, ShowsAGreyImageWithTheWireTipWhereTheCArmProjectsIt) {
  const std::string case_path = std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_right_ica.case";
  const tool::CaseParse the_case = tool::load_case(case_path);
  ASSERT_TRUE(the_case);
  ASSERT_FALSE(the_case->views.empty());
  const std::string shot = std::string(CATHBOX_TEST_OUT) + "/trainer_fluoro.png";
  FluoroShot f;
  ASSERT_TRUE(take_fluoro_shot("--case " + case_path + " --frames 150 --ms-per-frame 100", shot, f)) << "see " << shot << ".log";
  const auto& img = f.img;
  const Sidecar& s = f.s;
  const Viewport& hud = f.hud;
  int distinct = 0;
  int last = -1;
  for (int y = s.global.y; y < s.global.y + s.global.height; y += 7) {
    for (int x = s.global.x; x < s.global.x + s.global.width; x += 7) {
      if (hud.contains(static_cast<float>(x), static_cast<float>(y))) continue;
      const std::uint8_t* p = img->pixel(x, y);
      ASSERT_TRUE(p[0] == p[1] && p[1] == p[2]) << "grey at " << x << "," << y;
      distinct += p[0] != last ? 1 : 0;
      last = p[0];
    }
  }
  EXPECT_GT(distinct, 1000) << "an image, not a flat field";
  const glm::dvec2 tip = first_view_carm(*the_case, s.target).project_px(glm::dvec3(s.tip), s.global.width, s.global.height) +
                         glm::dvec2(s.global.x, s.global.y);
  ASSERT_TRUE(s.global.contains(static_cast<float>(tip.x), static_cast<float>(tip.y)) &&
              !hud.contains(static_cast<float>(tip.x), static_cast<float>(tip.y)))
      << "the tip at " << tip.x << "," << tip.y << " in the field";
  // The image shows the tools at the last pulse (15 a second, the autopilot holding the pedal),
  // the sidecar the tip at the last frame: up to 67 ms of travel apart, about 1 mm, ~4 px.
  int darkest = 255;
  for (int dy = -5; dy <= 5; ++dy) {
    for (int dx = -5; dx <= 5; ++dx) darkest = std::min<int>(darkest, img->pixel(static_cast<int>(tip.x) + dx, static_cast<int>(tip.y) + dy)[0]);
  }
  double ring = 0.0;
  for (int k = 0; k < 16; ++k) {
    const double a = 6.283185307 * k / 16.0;
    ring += img->pixel(static_cast<int>(tip.x + 12.0 * std::cos(a)), static_cast<int>(tip.y + 12.0 * std::sin(a)))[0];
  }
  EXPECT_LT(darkest, ring / 16.0 - 20.0) << "the platinum tip darker than around it";
}

// The session's fluoroscopy unit drives the view: the coiling case's guide catheter sits in the
// right ICA; with the pedal down, 6 mL injected from it make a contrast run, shown subtracted
// (DSA: what did not change is background grey). The right ICA's projected centre line is dark,
// the left ICA's (no flow from the right ICA reaches it) is background.
TEST(TrainerFluoroView, AnInjectionFromTheGuideFillsTheRightCarotidOnly) {
  const std::string case_path = std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_coiling.case";
  const tool::CaseParse the_case = tool::load_case(case_path);
  ASSERT_TRUE(the_case);
  ASSERT_FALSE(the_case->views.empty());
  const vessel::HclmReadResult model = vessel::load_hclm(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_aneurysm.hclm");
  ASSERT_TRUE(model.ok());
  const std::string dir = std::string(CATHBOX_TEST_OUT) + "/fluoro_injection";
  std::filesystem::create_directories(dir);
  // Mean grey along a segment's projected centre line (points in the main view, off the HUD).
  const auto run = [&](const std::string& name, bool inject, std::map<std::string, double>& grey, double& median) {
    const std::string script = dir + "/" + name + ".actions";
    std::ofstream(script) << "0 fluoro on\n" << (inject ? "300 inject 6 at 4\n" : "") << "3000 end\n";
    const std::string shot = dir + "/" + name + ".png";
    FluoroShot f;
    ASSERT_TRUE(take_fluoro_shot("--case " + case_path + " --script " + script + " --frames 40 --ms-per-frame 50", shot, f))
        << "see " << shot << ".log";
    const auto& img = f.img;
    const Sidecar& s = f.s;
    const Viewport& hud = f.hud;
    const flow::CArm carm = first_view_carm(*the_case, s.target);
    std::vector<int> all;
    for (int y = s.global.y; y < s.global.y + s.global.height; y += 5) {
      for (int x = s.global.x; x < s.global.x + s.global.width; x += 5) {
        if (!hud.contains(static_cast<float>(x), static_cast<float>(y))) all.push_back(img->pixel(x, y)[0]);
      }
    }
    ASSERT_FALSE(all.empty());
    std::nth_element(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(all.size() / 2), all.end());
    median = all[all.size() / 2];
    for (const vessel::Segment& seg : model.model.segments) {
      if (seg.name != "left_internal_carotid" && seg.name != "right_internal_carotid") continue;
      double sum = 0.0;
      int n = 0;
      for (const vessel::CenterlinePoint& c : seg.points) {
        const glm::dvec2 px = carm.project_px(c.pos_mm, s.global.width, s.global.height) + glm::dvec2(s.global.x, s.global.y);
        const auto x = static_cast<float>(px.x);
        const auto y = static_cast<float>(px.y);
        if (!s.global.contains(x, y) || hud.contains(x, y)) continue;
        sum += img->pixel(static_cast<int>(px.x), static_cast<int>(px.y))[0];
        ++n;
      }
      ASSERT_GT(n, 5) << seg.name << " in the field";
      grey[seg.name] = sum / n;
    }
  };
  std::map<std::string, double> injected;
  double background = 0.0;
  run("injected", true, injected, background);
  ASSERT_EQ(injected.size(), 2u);
  EXPECT_LT(injected["right_internal_carotid"], background - 25.0) << "the right ICA fills";
  EXPECT_NEAR(injected["left_internal_carotid"], background, 8.0) << "the left ICA does not";
}

// A `realistic` case opens in the fluoroscopic view without --view (and --view 3d overrides it).
TEST(TrainerFluoroView, ARealisticCaseOpensInFluoroscopy) {
  const std::string dir = std::string(CATHBOX_TEST_OUT) + "/realistic_case";
  std::filesystem::create_directories(dir);
  {
    std::ifstream in(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro_right_ica.case");
    std::ofstream out(dir + "/realistic.case");
    out << in.rdbuf() << "realistic\n";
  }
  std::filesystem::copy_file(std::string(CATHBOX_SOURCE_DIR) + "/cases/neuro.hclm", dir + "/neuro.hclm",
                             std::filesystem::copy_options::overwrite_existing);
  const auto grey_view = [&](const std::string& extra, const std::string& name) {
    const std::string shot = dir + "/" + name + ".png";
    const std::string cmd = std::string(CATHBOX_XVFB_RUN) + " -a -s '-screen 0 1280x800x24' " + CATHBOX_TRAINER +
                            " --headless --no-record --case " + dir + "/realistic.case --frames 2 --size 1280x720 " + extra +
                            " --screenshot " + shot + " > " + shot + ".log 2>&1";
    EXPECT_EQ(std::system(cmd.c_str()), 0) << "see " << shot << ".log";
    std::string error;
    const auto img = testing::read_png(shot, error);
    Sidecar s;
    if (!img || !read_sidecar(shot + ".txt", s)) return false;
    // Below the HUD, across the main view.
    for (int x = s.global.x + 10; x < s.global.x + s.global.width - 10; x += 37) {
      const std::uint8_t* p = img->pixel(x, s.global.y + s.global.height - 20);
      if (p[0] != p[1] || p[1] != p[2]) return false;
    }
    return true;
  };
  EXPECT_TRUE(grey_view("", "default")) << "realistic: fluoroscopy";
  EXPECT_FALSE(grey_view("--view 3d", "view3d")) << "--view 3d: the coloured 3D view";
}

TEST(TrainerHeadless, ScriptedRunReachesTheTargetPrintsTheSummaryIsDeterministicAndReplays) {
  const std::string dir = CATHBOX_TEST_OUT;
  for (const char* sub : {"/records_a", "/records_b"}) {
    std::filesystem::remove_all(dir + sub);
    std::filesystem::create_directories(dir + sub);
  }
  const std::string a = run_trainer("--headless --records " + dir + "/records_a", dir + "/headless_a.txt");
  const std::string b = run_trainer("--headless --records " + dir + "/records_b", dir + "/headless_b.txt");
  ASSERT_FALSE(a.empty()) << "see " << dir << "/headless_a.txt";
  EXPECT_EQ(a, b);
  for (const char* line : {"end of run", "procedure time", "tip path length", "wall contacts", "peak wall force",
                           "time above 100", "wrong-branch entries", "retractions", "peak insertion speed",
                           "tool changes", "peak hand force", "target                reached at", "path efficiency",
                           "fluoroscopy time      0.00 s"}) {  // the unit is there, the pedal never pressed
    EXPECT_NE(a.find(line), std::string::npos) << line << " missing in:\n" << a;
  }
  EXPECT_EQ(count_of(a, "target reached:"), 1U) << a;  // the run ends there
  const std::size_t at = a.find("tip path length");
  ASSERT_NE(at, std::string::npos);
  EXPECT_GT(std::atof(a.c_str() + at + 15), 100.0);  // the tip travelled up to the neck

  const std::string record = only_record_in(dir + "/records_a");
  ASSERT_NE(record.find(".cbxrec"), std::string::npos) << record;
  const std::string replayed = run_trainer("--headless --replay " + record, dir + "/headless_replay.txt");
  ASSERT_FALSE(replayed.empty()) << "see " << dir << "/headless_replay.txt";
  EXPECT_NE(replayed.find("state hashes checked"), std::string::npos) << replayed;
  EXPECT_EQ(replayed.find("MISMATCH"), std::string::npos) << replayed;
  // The same figures, replayed from the record.
  EXPECT_EQ(replayed.substr(replayed.find("procedure time")), a.substr(a.find("procedure time")));
}

}  // namespace
}  // namespace cathbox::app
