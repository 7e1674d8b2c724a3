#pragma once
// The tools of one fluoroscopic scene as the triangles the scene pass accumulates (no GL): each
// tool a closed tube of its shaft's material, its radio-opaque markers as tubes of their own
// (their mu less the shaft's, drawn inside it), thinner ones widened to a pixel with mu scaled
// to keep their attenuation across the line (thin_line). Used by FluoroRenderer and, compiled to
// WebAssembly, by the trainee page's fluoroscopy (host/wasm).
#include <cstdint>
#include <vector>

#include <glm/vec4.hpp>

#include "app/fluoro_inputs.hpp"
#include "app/tube_mesh.hpp"

namespace cathbox::app {

class FluoroToolMesh {
 public:
  static constexpr int kSides = 8;  // sides of a tool's tube

  // The scene's tools at `keV`, for an image whose pixel is `patient_pixel_mm` at the isocentre.
  void build(const FluoroScene& scene, double patient_pixel_mm, double keV);

  [[nodiscard]] const std::vector<float>& vertices() const { return vertices_; }           // x, y, z, mu, 0, 0
  [[nodiscard]] const std::vector<std::uint32_t>& indices() const { return indices_; }     // closed tubes
  // Every vertex lies within one of these spheres (centre mm, radius mm): a screen box's input.
  [[nodiscard]] const std::vector<glm::vec4>& spheres() const { return spheres_; }

 private:
  void add_tube(const std::vector<glm::vec3>& nodes, float radius_mm, float mu);
  TubeMesh tube_;
  std::vector<glm::vec3> marker_nodes_;
  std::vector<float> vertices_;
  std::vector<std::uint32_t> indices_;
  std::vector<glm::vec4> spheres_;
};

}  // namespace cathbox::app
