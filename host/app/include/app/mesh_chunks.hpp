#pragma once
// Spatial chunks of a triangle mesh for culling on the CPU: the triangles are reordered so that
// each cell of a uniform grid owns one contiguous index range with its bounding box. The views
// then draw only the ranges inside the view frustum (and, for the local view, within the fog
// distance), merging neighbouring ranges into one draw call. On a software rasteriser the
// per-triangle work dominates, so triangles that cannot be seen must not be submitted.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/mat4x4.hpp>
#include <glm/vec3.hpp>

namespace cathbox::app {

struct MeshChunk {
  std::uint32_t first_index = 0;
  std::uint32_t index_count = 0;
  glm::vec3 min_mm{0.0F};
  glm::vec3 max_mm{0.0F};
};

struct IndexRange {
  std::uint32_t first_index = 0;
  std::uint32_t index_count = 0;
};

struct ChunkedMesh {
  std::vector<std::uint32_t> triangles;  // the input triangles, reordered by chunk
  std::vector<MeshChunk> chunks;

  // Triangle indices out of range are dropped (never read).
  [[nodiscard]] static ChunkedMesh build(std::span<const glm::vec3> positions_mm,
                                         std::span<const std::uint32_t> triangles, float cell_mm);
};

// Ranges to draw for a camera: chunks that intersect the frustum of `view_projection` and,
// when max_distance_mm > 0, lie within that distance of `eye_mm`. Adjacent ranges merge.
void visible_ranges(std::span<const MeshChunk> chunks, const glm::mat4& view_projection,
                    const glm::vec3& eye_mm, float max_distance_mm, std::vector<IndexRange>& out);

// False only when the box is certainly outside the frustum (all corners beyond one plane).
[[nodiscard]] bool box_in_frustum(const glm::mat4& view_projection, const glm::vec3& min_mm,
                                  const glm::vec3& max_mm);

}  // namespace cathbox::app
