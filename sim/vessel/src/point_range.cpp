#include "vessel/point_range.hpp"

#include <cmath>
#include <cstdio>

namespace cathbox::vessel {
namespace {

[[nodiscard]] std::string number(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.6g", v);
  return buffer;
}

}  // namespace

std::string point_range_problem(const glm::dvec3& pos_mm, double radius_mm) {
  static constexpr const char* kAxis[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const double c = pos_mm[k];
    if (!std::isfinite(c)) return std::string(kAxis[k]) + " is not finite";
    if (std::abs(c) > kMaxCoordinate_mm) {
      return std::string(kAxis[k]) + " " + number(c) + " mm is outside ±" + number(kMaxCoordinate_mm) + " mm";
    }
  }
  if (!std::isfinite(radius_mm)) return "the radius is not finite";
  if (radius_mm > kMaxRadius_mm) {
    return "radius " + number(radius_mm) + " mm is above " + number(kMaxRadius_mm) + " mm";
  }
  return {};
}

}  // namespace cathbox::vessel
