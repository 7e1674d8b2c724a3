#pragma once
// Arc-length helpers on a drawn polyline (GL-free, session-free: the fluoroscopy's tool mesh and
// the stent view both use them, natively and in the browser's wasm build).
#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

namespace cathbox::app {

// The part of a polyline between two arc positions (mm from its first node), into `out`.
inline void polyline_part(std::span<const glm::vec3> nodes, double from_mm, double to_mm, std::vector<glm::vec3>& out) {
  out.clear();
  double arc = 0.0;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) {
    const double len = glm::length(nodes[i + 1] - nodes[i]);
    const double a0 = arc;
    const double a1 = arc + len;
    arc = a1;
    if (a1 <= from_mm || a0 >= to_mm || len <= 0.0) continue;
    const auto at = [&](double a) { return nodes[i] + static_cast<float>((a - a0) / len) * (nodes[i + 1] - nodes[i]); };
    if (out.empty()) out.push_back(at(std::max(a0, from_mm)));
    out.push_back(at(std::min(a1, to_mm)));
  }
}

[[nodiscard]] inline double polyline_length(std::span<const glm::vec3> nodes) {
  double s = 0.0;
  for (std::size_t i = 0; i + 1 < nodes.size(); ++i) s += glm::length(nodes[i + 1] - nodes[i]);
  return s;
}

}  // namespace cathbox::app
