#pragma once
// The surface patch of one junction: the convex hull of its rings without the rings' discs,
// checked to be a manifold patch bounded by exactly the ring edges, and paired into quads.
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::vessel::detail {

struct JunctionRing {
  bool tube_runs_forward = false;  // true when the tube uses the ring's edges m -> m+1
};

struct JunctionPatchResult {
  std::vector<std::vector<int>> faces;  // local point indices (ring r, point m -> r * M + m)
  std::string error;                    // empty on success
};

// `points` holds rings.size() rings of `ring_points` points each, in ring order.
[[nodiscard]] JunctionPatchResult build_junction_patch(const std::vector<glm::dvec3>& points,
                                                       const std::vector<JunctionRing>& rings, int ring_points);

}  // namespace cathbox::vessel::detail
