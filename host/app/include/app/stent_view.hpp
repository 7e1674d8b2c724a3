#pragma once
// Where a stent retriever's stent section begins on its push wire's drawn polyline: the
// renderers draw the push wire at its own radius up to that node and the stent section, from
// it, at the expanded stent's (session::ToolView::wire_radius_mm, radius_mm).
#include <algorithm>
#include <cstddef>
#include <span>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "session/scene_snapshot.hpp"

namespace cathbox::app {

// The node of a polyline (proximal to distal) `length_mm` back from its distal end (0 when the
// polyline is shorter, or empty).
[[nodiscard]] inline std::size_t node_back_from_tip(const std::vector<glm::vec3>& nodes, double length_mm) {
  if (nodes.empty()) return 0;
  std::size_t j = nodes.size() - 1;
  for (double along = 0.0; j > 0 && along < length_mm; --j) along += glm::length(nodes[j] - nodes[j - 1]);
  return j;
}

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

// The first node of the expanded stent section of a tool view drawn from `nodes`, or 0 when the
// whole tool is drawn at one radius (no stent, not expanded, or too few nodes to split).
[[nodiscard]] inline std::size_t expanded_stent_first_node(const session::ToolView& view, const std::vector<glm::vec3>& nodes) {
  if (!(view.stent_length_mm > 0.0F) || !(view.wire_radius_mm > 0.0F) || !(view.wire_radius_mm < view.radius_mm)) return 0;
  if (nodes.size() < 3) return 0;
  return node_back_from_tip(nodes, view.stent_length_mm);
}

}  // namespace cathbox::app
