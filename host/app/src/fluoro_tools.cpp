// The tools in a fluoroscopic scene (their triangles: FluoroToolMesh, fluoro_tool_mesh.cpp),
// drawn into the scene targets with the vessel.
#include "app/fluoro_renderer.hpp"
#include "app/gl.hpp"
#include "fluoro_render_parts.hpp"

namespace cathbox::app {

FluoroRenderer::Rect FluoroRenderer::build_tools(const FluoroScene& scene, const flow::CArm& carm, double keV, int width,
                                                 int height) {
  const double pixel_mm = carm.pixel_mm(width, height);
  tool_mesh_.build(scene, pixel_mm / carm.magnification(carm.isocenter_mm()), keV);
  ScreenBox box(carm, width, height);
  for (const glm::vec4& s : tool_mesh_.spheres()) box.add_sphere(glm::vec3(s), s.w);
  return box.rect();
}

void FluoroRenderer::draw_tools() {
  const std::vector<float>& tool_vertices = tool_mesh_.vertices();
  const std::vector<std::uint32_t>& tool_indices = tool_mesh_.indices();
  if (tool_indices.empty()) return;
  glBindVertexArray(tools_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, tools_vbo_);
  const std::size_t vbytes = tool_vertices.size() * sizeof(float);
  const std::size_t ibytes = tool_indices.size() * sizeof(std::uint32_t);
  if (vbytes > tools_vbo_bytes_) {
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vbytes), tool_vertices.data(), GL_STREAM_DRAW);
    tools_vbo_bytes_ = vbytes;
  } else {
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(vbytes), tool_vertices.data());
  }
  if (ibytes > tools_ebo_bytes_) {
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(ibytes), tool_indices.data(), GL_STREAM_DRAW);
    tools_ebo_bytes_ = ibytes;
  } else {
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(ibytes), tool_indices.data());
  }
  scene_shader_.set("u_tool", 1.0F);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(tool_indices.size()), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace cathbox::app
