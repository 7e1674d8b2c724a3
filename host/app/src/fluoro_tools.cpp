// The tools in a fluoroscopic scene: each a closed tube of kToolSides sides (radio-opaque markers
// as tubes of their own), drawn into the scene targets with the vessel.
#include <algorithm>
#include <span>

#include <glm/geometric.hpp>

#include "app/fluoro_renderer.hpp"
#include "app/stent_view.hpp"
#include "app/gl.hpp"
#include "flow/xray_material.hpp"
#include "fluoro_render_parts.hpp"

namespace cathbox::app {
namespace {

constexpr int kToolSides = 8;  // sides of a tool's tube

}  // namespace

FluoroRenderer::Rect FluoroRenderer::build_tools(const FluoroScene& scene, const flow::CArm& carm, double keV, int width,
                                                 int height) {
  tool_vertices_.clear();
  tool_indices_.clear();
  const double pixel_mm = carm.pixel_mm(width, height);
  const double patient_pixel_mm = pixel_mm / carm.magnification(carm.isocenter_mm());
  ScreenBox box(carm, width, height);
  const auto add_tube = [&](std::span<const glm::vec3> nodes, float radius_mm, float mu) {
    tube_.build(nodes, {}, radius_mm, kToolSides);
    if (tube_.positions_mm.empty()) return;
    // TubeMesh is open at its proximal end: close it with a cone, apex half a radius behind
    // (along the first piece of non-zero length).
    glm::vec3 t0{0.0F};
    for (std::size_t i = 1; i < nodes.size() && glm::length(t0) < 1e-6F; ++i) t0 = nodes[i] - nodes[0];
    if (glm::length(t0) < 1e-6F) return;
    t0 = glm::normalize(t0);
    const auto base = static_cast<std::uint32_t>(tool_vertices_.size() / 6);
    const auto ring = static_cast<std::uint32_t>(kToolSides);
    const auto apex = static_cast<std::uint32_t>(tube_.positions_mm.size());
    for (const glm::vec3& p : tube_.positions_mm) tool_vertices_.insert(tool_vertices_.end(), {p.x, p.y, p.z, mu, 0.0F, 0.0F});
    const glm::vec3 back = nodes[0] - 0.5F * radius_mm * t0;
    tool_vertices_.insert(tool_vertices_.end(), {back.x, back.y, back.z, mu, 0.0F, 0.0F});
    for (const std::uint32_t i : tube_.triangles) tool_indices_.push_back(base + i);
    for (std::uint32_t k = 0; k < ring; ++k) tool_indices_.insert(tool_indices_.end(), {base + (k + 1) % ring, base + k, base + apex});
    // Every vertex lies within radius_mm of a node (the tube's rings, the cone's apex).
    for (const glm::vec3& n : nodes) box.add_sphere(n, radius_mm);
  };
  for (const FluoroTool& tool : scene.tools) {
    if (tool.nodes_mm.size() < 2) continue;
    const ThinLine line = thin_line(tool.radius_mm, patient_pixel_mm);
    const auto shaft_mu = static_cast<float>(flow::linear_attenuation_per_mm(tool.material, keV));
    add_tube(tool.nodes_mm, line.radius_mm, shaft_mu * line.mu_scale);
    const double length = polyline_length(tool.nodes_mm);
    for (const FluoroMarker& m : tool.markers) {
      polyline_part(tool.nodes_mm, length - m.from_tip_mm - m.length_mm, length - m.from_tip_mm, marker_nodes_);
      if (marker_nodes_.size() < 2) continue;
      const auto mu = static_cast<float>(flow::linear_attenuation_per_mm(m.material, keV)) - shaft_mu;
      add_tube(marker_nodes_, line.radius_mm, mu * line.mu_scale);
    }
  }
  return box.rect();
}

void FluoroRenderer::draw_tools() {
  if (tool_indices_.empty()) return;
  glBindVertexArray(tools_vao_);
  glBindBuffer(GL_ARRAY_BUFFER, tools_vbo_);
  const std::size_t vbytes = tool_vertices_.size() * sizeof(float);
  const std::size_t ibytes = tool_indices_.size() * sizeof(std::uint32_t);
  if (vbytes > tools_vbo_bytes_) {
    glBufferData(GL_ARRAY_BUFFER, static_cast<GLsizeiptr>(vbytes), tool_vertices_.data(), GL_STREAM_DRAW);
    tools_vbo_bytes_ = vbytes;
  } else {
    glBufferSubData(GL_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(vbytes), tool_vertices_.data());
  }
  if (ibytes > tools_ebo_bytes_) {
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, static_cast<GLsizeiptr>(ibytes), tool_indices_.data(), GL_STREAM_DRAW);
    tools_ebo_bytes_ = ibytes;
  } else {
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, 0, static_cast<GLsizeiptr>(ibytes), tool_indices_.data());
  }
  scene_shader_.set("u_tool", 1.0F);
  glDrawElements(GL_TRIANGLES, static_cast<GLsizei>(tool_indices_.size()), GL_UNSIGNED_INT, nullptr);
  glBindVertexArray(0);
}

}  // namespace cathbox::app
