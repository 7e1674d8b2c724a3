#pragma once
// The pieces of subdivide() (subdivision.cpp) that its other files share: the refiner's primvar,
// the parent-to-child vertex numbering, the quad split, and the kMasks path's steps, whose
// definitions are in subdivision_last_step.cpp (the last refinement step by hand and its faces)
// and subdivision_limit_masks.cpp (limit positions and normals from each vertex's one-ring).
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <type_traits>
#include <vector>

#include <sys/mman.h>
#include <unistd.h>

#include <glm/geometric.hpp>
#include <opensubdiv/far/topologyLevel.h>
#include <opensubdiv/far/topologyRefiner.h>

#include "vessel/subdivision.hpp"

namespace cathbox::vessel::detail {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

// Primvar for OpenSubdiv's refiner (the interface it expects: Clear and AddWithWeight).
// Single precision: positions in mm up to a few hundred mm keep ~1e-5 mm, and half the memory
// traffic makes refinement noticeably faster.
// Trivially constructible, so scratch arrays of it that are fully overwritten are not zeroed first.
struct Point {
  glm::vec3 p;
  void Clear(void* = nullptr) { p = glm::vec3(0.0f); }
  void AddWithWeight(const Point& src, float weight) { p += weight * src.p; }
};
static_assert(std::is_trivially_default_constructible_v<Point>);

// Maps the whole pages inside [data, data + bytes) writable in one call (MADV_POPULATE_WRITE,
// Linux 5.14+) instead of one page fault per 4 KB page as they are first written; the buffers
// here are written in full right after. Advice only: where it is unsupported the pages fault in.
inline void prefault(const void* data, std::size_t bytes) {
#ifdef MADV_POPULATE_WRITE
  static const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto begin = (reinterpret_cast<std::uintptr_t>(data) + page - 1) & ~(page - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(page - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#else
  (void)data;
  (void)bytes;
#endif
}

// The first corner (0 or 1) of the shorter diagonal of quad v: 0 when |p0 - p2| <= |p1 - p3| as
// glm::length gives them. The squared lengths decide without a square root except when the
// second is the smaller: the rounded roots may still be equal then, which is a tie (corner 0).
[[nodiscard]] inline int shorter_diagonal(const std::vector<glm::vec3>& p, const int* v) {
  const glm::vec3 d02 = p[static_cast<std::size_t>(v[0])] - p[static_cast<std::size_t>(v[2])];
  const glm::vec3 d13 = p[static_cast<std::size_t>(v[1])] - p[static_cast<std::size_t>(v[3])];
  const float a = glm::dot(d02, d02);
  const float b = glm::dot(d13, d13);
  return a <= b || std::sqrt(a) <= std::sqrt(b) ? 0 : 1;
}

// Quad v as two triangles, split along its shorter diagonal, written to t[0..5].
inline void split_quad(const std::vector<glm::vec3>& p, const int* v, std::uint32_t* t) {
  const int s = shorter_diagonal(p, v);
  t[0] = static_cast<std::uint32_t>(v[s]);
  t[1] = static_cast<std::uint32_t>(v[s + 1]);
  t[2] = static_cast<std::uint32_t>(v[s + 2]);
  t[3] = static_cast<std::uint32_t>(v[s]);
  t[4] = static_cast<std::uint32_t>(v[s + 2]);
  t[5] = static_cast<std::uint32_t>(v[(s + 3) % 4]);
}

// Unit normal from a (possibly unoriented) direction, turned to the side of `outward`; falls back
// to `outward` when the direction is degenerate.
[[nodiscard]] glm::vec3 oriented_normal(const glm::dvec3& n, const glm::dvec3& outward);

// The index in level L of the child vertex of a level L-1 vertex, face or edge.
//  RefinerChildren: as the refiner recorded it (it refined level L itself).
//  UniformChildren: as uniform refinement numbers them (Vtr::Refinement, vertices not ordered
//  from faces first): the children of the vertices, then of the faces, then of the edges, each
//  in parent order. A test checks that both give the same mesh.
struct RefinerChildren {
  static constexpr bool kInOrder = false;
  const Far::TopologyLevel* parent;
  [[nodiscard]] int vertex(int v) const { return parent->GetVertexChildVertex(v); }
  [[nodiscard]] int face(int f) const { return parent->GetFaceChildVertex(f); }
  [[nodiscard]] int edge(int e) const { return parent->GetEdgeChildVertex(e); }
};
struct UniformChildren {
  static constexpr bool kInOrder = true;
  int num_vertices = 0;
  int num_faces = 0;
  explicit UniformChildren(const Far::TopologyLevel& parent)
      : num_vertices(parent.GetNumVertices()), num_faces(parent.GetNumFaces()) {}
  [[nodiscard]] int vertex(int v) const { return v; }
  [[nodiscard]] int face(int f) const { return num_vertices + f; }
  [[nodiscard]] int edge(int e) const { return num_vertices + num_faces + e; }
  [[nodiscard]] int total(const Far::TopologyLevel& parent) const { return num_vertices + num_faces + parent.GetNumEdges(); }
};

// The last refinement step of a closed, manifold mesh without creases, bit for bit as
// Far::PrimvarRefiner::Interpolate does it (subdivision_last_step.cpp).
void refine_smooth_last_level(const Far::TopologyLevel& parent, const UniformChildren& children, const Point* src,
                              Point* dst);

// True when every vertex of the level takes the smooth rule and every edge has two faces and
// no sharpness: a closed manifold without creases, so every finer level is one too.
[[nodiscard]] bool is_smooth_closed(const Far::TopologyLevel& level);

// The faces of level L (all quads) as two triangles each, straight from level L-1 (`parent`),
// appended in level L's face order, each with the region of the control face it descends from.
void emit_child_quads(const Far::TopologyRefiner& refiner, int parent_level, const UniformChildren& children,
                      const std::vector<FaceRegion>& control_regions, SurfaceMesh& out);

// Catmull-Clark limit positions and normals of the vertices of level L from level L-1's topology
// and level L's points `src` (subdivision_limit_masks.cpp). UniformChildren: appended to `out`'s
// positions and normals (reserved by the caller); RefinerChildren: written by index (sized by
// the caller). Level L-1 must be manifold.
void limit_by_masks(const Far::TopologyLevel& parent, const UniformChildren& children, const Point* src, SurfaceMesh& out);
void limit_by_masks(const Far::TopologyLevel& parent, const RefinerChildren& children, const Point* src, SurfaceMesh& out);

}  // namespace cathbox::vessel::detail
