#include "tube_fixture.hpp"

#include <cmath>

namespace cathbox::app::testing {

FixtureMesh straight_tube(float x0_mm, float x1_mm, float radius_mm, int rings, int sides) {
  FixtureMesh m;
  const auto s = static_cast<std::uint32_t>(sides);
  for (int i = 0; i < rings; ++i) {
    const float x = x0_mm + (x1_mm - x0_mm) * static_cast<float>(i) / static_cast<float>(rings - 1);
    for (int k = 0; k < sides; ++k) {
      const float a = 6.2831853F * static_cast<float>(k) / static_cast<float>(sides);
      const glm::vec3 n{0.0F, std::cos(a), std::sin(a)};
      m.positions_mm.push_back(glm::vec3(x, 0.0F, 0.0F) + radius_mm * n);
      m.normals.push_back(n);
    }
  }
  for (std::uint32_t i = 0; i + 1 < static_cast<std::uint32_t>(rings); ++i) {
    for (std::uint32_t k = 0; k < s; ++k) {
      const std::uint32_t a = i * s + k;
      const std::uint32_t b = i * s + (k + 1) % s;
      m.triangles.insert(m.triangles.end(), {a, b, b + s, a, b + s, a + s});
    }
  }
  // Caps: a centre vertex at each end.
  const auto c0 = static_cast<std::uint32_t>(m.positions_mm.size());
  m.positions_mm.emplace_back(x0_mm, 0.0F, 0.0F);
  m.normals.emplace_back(-1.0F, 0.0F, 0.0F);
  m.positions_mm.emplace_back(x1_mm, 0.0F, 0.0F);
  m.normals.emplace_back(1.0F, 0.0F, 0.0F);
  const std::uint32_t last = (static_cast<std::uint32_t>(rings) - 1) * s;
  for (std::uint32_t k = 0; k < s; ++k) {
    m.triangles.insert(m.triangles.end(), {c0, (k + 1) % s, k});
    m.triangles.insert(m.triangles.end(), {c0 + 1, last + k, last + (k + 1) % s});
  }
  return m;
}

}  // namespace cathbox::app::testing
