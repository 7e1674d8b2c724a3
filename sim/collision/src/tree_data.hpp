#pragma once
// The flat arrays behind an ObbTree. Nodes and triangle blocks are 4-wide structures of arrays
// so that one node or one leaf is tested with a handful of float vector operations.
#include <cstdint>
#include <limits>
#include <vector>

#include <glm/vec3.hpp>

#include "collision/obb_tree.hpp"
#include "huge_page_allocator.hpp"
#include "simd.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::collision::detail {

// A child slot holds a wide-node index (>= 0), a leaf (-1 - block index) or nothing.
constexpr std::int32_t kEmptySlot = std::numeric_limits<std::int32_t>::min();
inline bool is_leaf(std::int32_t slot) { return slot < 0 && slot != kEmptySlot; }
inline std::int32_t leaf_block(std::int32_t slot) { return -1 - slot; }

// Four boxes side by side: row r of the 15 rows holds one scalar for the four lanes:
// rows 0-2 the centre, rows 3 + 3k + c component c of axis k, rows 12-14 the half extents.
// Empty lanes have a centre far away and zero extent, so their distance is +inf.
constexpr int kBoxRows = 15;
struct alignas(16) BoxLanes {
  float row[kBoxRows][4];
};

struct alignas(64) WideNode {  // exactly four cache lines
  BoxLanes boxes;
  std::int32_t child[4];
};
static_assert(sizeof(WideNode) == 256);

// Up to four triangles, rows as for boxes: corners a, b, c (the mesh's floats, exactly), unit
// normal n and the dual basis (u, v) giving barycentric coordinates of the projection. Empty lanes sit far away; slivers have u = v = n = 0, which
// makes their float lower bound 0 so they always get the exact test.
enum TriangleRow : int { kRowA = 0, kRowB = 3, kRowC = 6, kRowN = 9, kRowU = 12, kRowV = 15,
                         kTriangleRows = 18 };
struct alignas(64) TriangleBlock {
  float row[kTriangleRows][4];
  std::int32_t face[4];     // mesh triangle index, -1 for empty lanes
  vessel::FaceRegion region;  // one per leaf: every leaf lies inside one region's subtree
};
static_assert(sizeof(TriangleBlock) == 320);

struct TreeData {
  std::uint64_t id = 0;  // distinguishes trees, so a hint filled by another tree is never used
  double coherence_margin_mm = 0.25;
  double scale_mm = 0.0;  // sum of the largest absolute coordinates, for the float error bound
  std::vector<WideNode, HugePageAllocator<WideNode>> nodes;  // nodes[0] is the root
  std::vector<TriangleBlock, HugePageAllocator<TriangleBlock>> blocks;
  // Mesh copy in double for the exact stage.
  std::vector<glm::dvec3> positions;
  std::vector<std::uint32_t> triangles;       // 3 per mesh triangle
  std::vector<vessel::FaceRegion> regions;    // per mesh triangle
  std::vector<glm::dvec3> face_normals;       // unit, per mesh triangle (0 for dropped ones)
  std::vector<glm::dvec3> vertex_normals;     // angle-weighted pseudo-normals
  std::vector<std::int32_t> opposite;         // per half-edge 3*t+k: neighbour triangle, -1 none
  std::vector<std::uint32_t> valence;         // kept triangles per vertex
  TreeStats stats;
};

}  // namespace cathbox::collision::detail
