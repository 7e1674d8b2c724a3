#pragma once
// Test fixture only: a closed straight tube along +X (radius r, from x0 to x1, flat end caps),
// with outward normals, standing in for a vessel so the renderer can be checked on its own.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::app::testing {

struct FixtureMesh {
  std::vector<glm::vec3> positions_mm;
  std::vector<glm::vec3> normals;
  std::vector<std::uint32_t> triangles;
};

[[nodiscard]] FixtureMesh straight_tube(float x0_mm, float x1_mm, float radius_mm, int rings,
                                        int sides);

}  // namespace cathbox::app::testing
