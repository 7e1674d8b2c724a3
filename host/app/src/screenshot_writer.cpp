#include "app/screenshot_writer.hpp"

#include <fstream>

#include <glm/gtc/type_ptr.hpp>

#include "app/frame_capture.hpp"
#include "app/png_writer.hpp"

namespace cathbox::app {
namespace {

void print_matrix(std::ofstream& out, const char* name, const glm::mat4& m) {
  out << name;
  const float* v = glm::value_ptr(m);
  for (int i = 0; i < 16; ++i) out << ' ' << v[i];
  out << '\n';
}

void print_rect(std::ofstream& out, const char* name, const Viewport& v) {
  out << name << ' ' << v.x << ' ' << v.y << ' ' << v.width << ' ' << v.height << '\n';
}

}  // namespace

base::Status<> write_screenshot(const std::string& path, const ScreenshotScene& scene,
                                const session::SceneSnapshot& s, int fb_width, int fb_height) {
  const Image img = FrameCapture::read_back_buffer(fb_width, fb_height);
  if (base::Status<> png = PngWriter::write_file(path, img); !png) return png;
  std::ofstream out(path + ".txt");
  out << "size " << fb_width << ' ' << fb_height << '\n';
  out << "vessel_file " << scene.vessel_file << '\n';
  print_rect(out, "global", scene.layout.global);
  print_rect(out, "local", scene.layout.local);
  print_rect(out, "hud", scene.hud);
  print_matrix(out, "view", scene.view);
  print_matrix(out, "proj", scene.projection);
  if (scene.target_mm) {
    const glm::vec3 t = *scene.target_mm;
    out << "target " << t.x << ' ' << t.y << ' ' << t.z << ' ' << scene.target_radius_mm << '\n';
  }
  for (int i = 0; i < s.tool_count; ++i) {
    for (const glm::vec3& p : s.tools[static_cast<std::size_t>(i)].nodes_mm) {
      out << "node " << i << ' ' << p.x << ' ' << p.y << ' ' << p.z << '\n';
    }
  }
  out << "tip " << s.tip_mm.x << ' ' << s.tip_mm.y << ' ' << s.tip_mm.z << '\n';
  out << "sim_time_us " << s.sim_time_us << '\n';
  if (!out) return base::Error{path + ".txt: write failed"};
  return base::Ok{};
}

}  // namespace cathbox::app
