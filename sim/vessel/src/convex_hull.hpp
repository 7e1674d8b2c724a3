#pragma once
// 3D convex hull of a small point set (a junction's rings), incremental, O(n^2).
// Exact coplanarities (regular rings, symmetric branches) are resolved by a tiny deterministic
// perturbation used only for the combinatorial decisions.
#include <array>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::vessel::detail {

// Outward-oriented (counter-clockwise seen from outside) hull triangles as point indices.
// Points strictly inside the hull are not referenced. Empty when the points span no volume.
[[nodiscard]] std::vector<std::array<int, 3>> convex_hull(const std::vector<glm::dvec3>& points);

}  // namespace cathbox::vessel::detail
