#include "app/gpu_mesh.hpp"

#include "app/gl.hpp"

namespace cathbox::app {

GpuMesh::~GpuMesh() {
  if (vao_ != 0) glDeleteVertexArrays(1, &vao_);
  if (vbo_ != 0) glDeleteBuffers(1, &vbo_);
  if (ebo_ != 0) glDeleteBuffers(1, &ebo_);
}

void GpuMesh::upload(std::span<const glm::vec3> positions, std::span<const glm::vec3> normals,
                     std::span<const std::uint32_t> triangles, bool dynamic) {
  if (vao_ == 0) {
    glGenVertexArrays(1, &vao_);
    glGenBuffers(1, &vbo_);
    glGenBuffers(1, &ebo_);
    glBindVertexArray(vao_);
    glBindBuffer(GL_ARRAY_BUFFER, vbo_);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo_);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float), nullptr);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 3, GL_FLOAT, GL_FALSE, 6 * sizeof(float),
                          reinterpret_cast<const void*>(3 * sizeof(float)));
  }
  glBindVertexArray(vao_);
  interleaved_.resize(positions.size() * 6);
  for (std::size_t i = 0; i < positions.size(); ++i) {
    const glm::vec3 n = i < normals.size() ? normals[i] : glm::vec3(0, 0, 1);
    float* v = interleaved_.data() + 6 * i;
    v[0] = positions[i].x;
    v[1] = positions[i].y;
    v[2] = positions[i].z;
    v[3] = n.x;
    v[4] = n.y;
    v[5] = n.z;
  }
  const std::size_t vbytes = interleaved_.size() * sizeof(float);
  const std::size_t ibytes = triangles.size() * sizeof(std::uint32_t);
  const GLenum usage = dynamic ? GL_STREAM_DRAW : GL_STATIC_DRAW;
  glBindBuffer(GL_ARRAY_BUFFER, vbo_);
  if (vbytes > vbo_capacity_ || !dynamic) {
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vbytes), interleaved_.data(), usage);
    vbo_capacity_ = vbytes;
  } else {
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(vbytes), interleaved_.data());
  }
  // The element buffer binding is part of the VAO state, bound above.
  if (ibytes > ebo_capacity_ || !dynamic) {
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(ibytes), triangles.data(), usage);
    ebo_capacity_ = ibytes;
  } else {
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(ibytes), triangles.data());
  }
  index_count_ = triangles.size();
  glBindVertexArray(0);
  if (!dynamic) std::vector<float>().swap(interleaved_);  // static data lives on the GPU now
}

void GpuMesh::draw() const {
  if (index_count_ == 0) return;
  glBindVertexArray(vao_);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(index_count_), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace cathbox::app

namespace cathbox::app {

void GpuMesh::draw_ranges(std::span<const IndexRange> ranges) const {
  if (index_count_ == 0 || ranges.empty()) return;
  glBindVertexArray(vao_);
  for (const IndexRange& r : ranges) {
    if (r.first_index + r.index_count > index_count_) continue;
    glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(r.index_count), GL_UNSIGNED_INT,
                   reinterpret_cast<const void*>(static_cast<std::uintptr_t>(r.first_index) * sizeof(std::uint32_t)));
  }
  glBindVertexArray(0);
}

}  // namespace cathbox::app
