#pragma once
// A lumen path for SheathFriction's tests: points given proximal first (the entry first) become
// the path's vertices distal first, each with its depth along the path and the inner tool's
// stiffness, radius, clearance and friction there.
#include <cstdint>
#include <functional>
#include <vector>

#include <glm/geometric.hpp>

#include "tool/sheath_friction.hpp"

namespace cathbox::tool::testing {

struct SheathPathTool {
  std::function<double(std::size_t)> ei_Nmm2;  // by point, proximal first
  double radius_mm = 0.125;
  double clearance_mm = 0.09;
  double mu = 0.0;
};

inline std::vector<SheathVertex> sheath_path(const std::vector<glm::dvec3>& proximal_first, const SheathPathTool& tool) {
  std::vector<double> depths{0.0};
  for (std::size_t i = 1; i < proximal_first.size(); ++i) {
    depths.push_back(depths.back() + glm::length(proximal_first[i] - proximal_first[i - 1]));
  }
  std::vector<SheathVertex> distal_first;
  for (std::size_t i = proximal_first.size(); i-- > 0;) {
    SheathVertex v;
    v.point_mm = proximal_first[i];
    v.node = static_cast<std::uint32_t>(i);
    v.depth_mm = depths[i];
    v.inner_ei_Nmm2 = tool.ei_Nmm2 ? tool.ei_Nmm2(i) : 0.0;
    v.inner_radius_mm = tool.radius_mm;
    v.clearance_mm = tool.clearance_mm;
    v.mu = tool.mu;
    distal_first.push_back(v);
  }
  return distal_first;
}

}  // namespace cathbox::tool::testing
