#pragma once
// Topological and geometric checks of a SurfaceMesh: closed, manifold, consistently oriented,
// Euler characteristic, enclosed volume, self-intersections. Used by the tests, the CLI and
// anyone who loads a mesh from elsewhere.
#include <cstddef>

#include "vessel/surface_mesh.hpp"

namespace cathbox::vessel {

struct MeshAnalysis {
  std::size_t vertices = 0;
  std::size_t edges = 0;
  std::size_t triangles = 0;
  std::size_t boundary_edges = 0;        // edges with one triangle
  std::size_t nonmanifold_edges = 0;     // edges with more than two triangles
  std::size_t misoriented_edges = 0;     // edges two triangles run in the same direction
  std::size_t nonmanifold_vertices = 0;  // vertices whose triangles do not form one fan
  std::size_t degenerate_triangles = 0;  // zero area or repeated vertex
  int euler_characteristic = 0;          // V - E + F
  double signed_volume_mm3 = 0.0;        // > 0 for an outward-oriented closed surface
  double area_mm2 = 0.0;

  [[nodiscard]] bool closed() const { return boundary_edges == 0; }
  [[nodiscard]] bool manifold() const { return nonmanifold_edges == 0 && nonmanifold_vertices == 0; }
  [[nodiscard]] bool consistently_oriented() const { return misoriented_edges == 0; }
};

[[nodiscard]] MeshAnalysis analyze_mesh(const SurfaceMesh& mesh);

// Pairs of triangles that share no vertex and intersect (edge through the other's interior).
// Counts up to `limit` pairs.
[[nodiscard]] std::size_t count_self_intersections(const SurfaceMesh& mesh, std::size_t limit = 1);

}  // namespace cathbox::vessel
