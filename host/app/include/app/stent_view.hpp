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

#include "app/polyline.hpp"
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

// The first node of the expanded stent section of a tool view drawn from `nodes`, or 0 when the
// whole tool is drawn at one radius (no stent, not expanded, or too few nodes to split).
[[nodiscard]] inline std::size_t expanded_stent_first_node(const session::ToolView& view, const std::vector<glm::vec3>& nodes) {
  if (!(view.stent_length_mm > 0.0F) || !(view.wire_radius_mm > 0.0F) || !(view.wire_radius_mm < view.radius_mm)) return 0;
  if (nodes.size() < 3) return 0;
  return node_back_from_tip(nodes, view.stent_length_mm);
}

}  // namespace cathbox::app
