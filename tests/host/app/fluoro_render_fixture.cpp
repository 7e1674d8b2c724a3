#include "fluoro_render_fixture.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

namespace cathbox::app::fluoro_test {

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

}  // namespace cathbox::app::fluoro_test
