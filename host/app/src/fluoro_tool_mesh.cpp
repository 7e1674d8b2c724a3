#include "app/fluoro_tool_mesh.hpp"

#include <algorithm>
#include <span>

#include <glm/geometric.hpp>

#include "app/fluoro_image_model.hpp"
#include "app/polyline.hpp"
#include "flow/xray_material.hpp"

namespace cathbox::app {

void FluoroToolMesh::add_tube(const std::vector<glm::vec3>& nodes, float radius_mm, float mu) {
  tube_.build(nodes, {}, radius_mm, kSides);
  if (tube_.positions_mm.empty()) return;
  // TubeMesh is open at its proximal end: close it with a cone, apex half a radius behind
  // (along the first piece of non-zero length).
  glm::vec3 t0{0.0F};
  for (std::size_t i = 1; i < nodes.size() && glm::length(t0) < 1e-6F; ++i) t0 = nodes[i] - nodes[0];
  if (glm::length(t0) < 1e-6F) return;
  t0 = glm::normalize(t0);
  const auto base = static_cast<std::uint32_t>(vertices_.size() / 6);
  const auto ring = static_cast<std::uint32_t>(kSides);
  const auto apex = static_cast<std::uint32_t>(tube_.positions_mm.size());
  for (const glm::vec3& p : tube_.positions_mm) vertices_.insert(vertices_.end(), {p.x, p.y, p.z, mu, 0.0F, 0.0F});
  const glm::vec3 back = nodes[0] - 0.5F * radius_mm * t0;
  vertices_.insert(vertices_.end(), {back.x, back.y, back.z, mu, 0.0F, 0.0F});
  for (const std::uint32_t i : tube_.triangles) indices_.push_back(base + i);
  for (std::uint32_t k = 0; k < ring; ++k) indices_.insert(indices_.end(), {base + (k + 1) % ring, base + k, base + apex});
  // Every vertex lies within radius_mm of a node (the tube's rings, the cone's apex).
  for (const glm::vec3& n : nodes) spheres_.emplace_back(n, radius_mm);
}

void FluoroToolMesh::build(const FluoroScene& scene, double patient_pixel_mm, double keV) {
  vertices_.clear();
  indices_.clear();
  spheres_.clear();
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
}

}  // namespace cathbox::app
