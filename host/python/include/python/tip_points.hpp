#pragma once
// Points along a tool back from its tip, every spacing_mm of arc length (linear between nodes):
// the environments' "tracking" and "state" observations. Past the proximal end of the polyline
// the first node is repeated; no nodes give zeros.
//
//   std::vector<glm::dvec3> out(16);
//   python::points_from_tip(snapshot.tools[0].positions_mm, 5.0, out);  // out[0] = the tip
#include <span>

#include <glm/vec3.hpp>

namespace cathbox::python {

// nodes_mm runs from the entry to the tip; fills every element of out.
void points_from_tip(std::span<const glm::dvec3> nodes_mm, double spacing_mm, std::span<glm::dvec3> out);

}  // namespace cathbox::python
