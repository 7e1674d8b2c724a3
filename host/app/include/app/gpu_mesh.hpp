#pragma once
// An indexed triangle mesh in GPU buffers (positions and normals interleaved). The vessel is
// uploaded once (static); tools are re-uploaded every frame into buffers that only grow.
#include <cstdint>
#include <span>
#include <vector>

#include <glm/vec3.hpp>

#include "app/mesh_chunks.hpp"

namespace cathbox::app {

class GpuMesh {
 public:
  GpuMesh() = default;
  ~GpuMesh();
  GpuMesh(const GpuMesh&) = delete;
  GpuMesh& operator=(const GpuMesh&) = delete;

  void upload(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
              std::span<const std::uint32_t> triangles, bool dynamic);
  void draw() const;
  // Draws index ranges (in indices, not bytes) of the uploaded triangles.
  void draw_ranges(std::span<const IndexRange> ranges) const;
  [[nodiscard]] std::size_t index_count() const { return index_count_; }

 private:
  unsigned vao_ = 0;
  unsigned vbo_ = 0;
  unsigned ebo_ = 0;
  std::size_t vbo_capacity_ = 0;  // bytes
  std::size_t ebo_capacity_ = 0;  // bytes
  std::size_t index_count_ = 0;
  std::vector<float> interleaved_;
};

}  // namespace cathbox::app
