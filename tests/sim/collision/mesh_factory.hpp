#pragma once
// Synthetic vessel-like meshes for the collision tests and benchmark: closed, outward-oriented
// tubes with end caps along a curve (regions: segments and caps), bumpy spheres, and open
// triangle soups with slivers and degenerate triangles.
#include <cstdint>
#include <functional>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::collision::testing {

struct TubeSpec {
  std::function<glm::dvec3(double)> centerline;  // s in [0, 1]
  std::function<double(double)> radius_mm;       // s in [0, 1]
  int rings = 64;        // cross-sections along the curve
  int sides = 16;        // vertices per cross-section
  int segments = 4;      // regions along the tube (kSegment ids 0..segments-1)
  int junction_every = 0;  // if > 0, every n-th segment region is labelled a junction instead
};

// Closed tube with a fan cap at each end (kCap regions).
[[nodiscard]] vessel::SurfaceMesh make_tube(const TubeSpec& spec);

// A (2,3) torus-knot tube of about rings * sides * 2 triangles, vessel-sized (radius ~1.5 mm).
[[nodiscard]] vessel::SurfaceMesh make_knot_tube(int rings, int sides);

// A sphere with radial noise (star-shaped, so closed and simple), regions by octant.
[[nodiscard]] vessel::SurfaceMesh make_bumpy_sphere(int stacks, int slices, double radius_mm,
                                                    double noise, std::uint32_t seed);

// n random triangles of mixed sizes in a 20 mm box, a few slivers and exactly degenerate ones.
[[nodiscard]] vessel::SurfaceMesh make_soup(int n, std::uint32_t seed);

// Flips every triangle if the signed volume is negative, so the mesh faces outward.
void orient_outward(vessel::SurfaceMesh& mesh);

}  // namespace cathbox::collision::testing
