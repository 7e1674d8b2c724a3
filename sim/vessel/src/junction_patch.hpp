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

// A ring's frame at the junction: `out` the unit direction its tube leaves the junction in; ring
// point m is at centre + radius (cos(2 pi m / M) normal + sin(2 pi m / M) binormal).
struct JunctionRingFrame {
  glm::dvec3 out{0.0, 0.0, 1.0};
  glm::dvec3 normal{1.0, 0.0, 0.0};
  glm::dvec3 binormal{0.0, 1.0, 0.0};
  glm::dvec3 center{0.0};
};

// The fallback for a junction whose rings' own hull is no patch (branches overlap, a ring inside
// the others' hull): the connectivity is taken from the hull of the rings moved onto the unit
// sphere, each a small circle about the direction its tube leaves in (the junction's Gauss map;
// directions closer than 10 degrees pushed apart, circles kept from touching). Points on a sphere
// are all on their hull and each circle is a face of it, so the patch is always a sphere with one
// hole per ring bounded by exactly the ring edges; its faces then join the rings' real points
// (Baerentzen, Misztal & Welnicka, "Converting skeletal structures to quad dominant meshes",
// Computers & Graphics 2012, build a node's patch from the hull of its branches' directions).
// The patch is topologically sound; where branches really overlap it may fold through them.
[[nodiscard]] JunctionPatchResult build_spherical_junction_patch(const std::vector<glm::dvec3>& points,
                                                                 const std::vector<JunctionRing>& rings,
                                                                 const std::vector<JunctionRingFrame>& frames,
                                                                 int ring_points);

}  // namespace cathbox::vessel::detail
