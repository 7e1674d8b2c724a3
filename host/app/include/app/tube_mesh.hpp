#pragma once
// Triangle geometry of a tool drawn as a tube along its node polyline: a ring of `sides`
// vertices per node, oriented by the node's frame (or, without frames, by parallel transport),
// and a rounded cap at the distal end. Rebuilt in place each frame without reallocating once
// the buffers have grown to the tool's node count.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::app {

struct TubeMesh {
  std::vector<glm::vec3> positions_mm;
  std::vector<glm::vec3> normals;
  std::vector<std::uint32_t> triangles;

  // `frames` (optional, one per node) gives a direction normal to the tool at each node.
  // Fewer than two distinct nodes give an empty mesh.
  void build(std::span<const glm::vec3> nodes_mm, std::span<const glm::vec3> frames,
             float radius_mm, int sides = 8);

  [[nodiscard]] static std::size_t vertex_count(std::size_t nodes, int sides);
  [[nodiscard]] static std::size_t index_count(std::size_t nodes, int sides);
};

}  // namespace cathbox::app
