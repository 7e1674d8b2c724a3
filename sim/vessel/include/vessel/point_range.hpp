#pragma once
// The physical range of a centreline point. A human body is well under a metre across, and a
// scanner's patient coordinates sit at most a metre or so off their origin, so a coordinate
// beyond ±kMaxCoordinate_mm or a radius beyond kMaxRadius_mm (the widest aortic aneurysms are
// ~50 mm in radius) is a broken file, not anatomy. Every reader checks it (HCLM, the importers)
// so that no later stage meets a value whose arithmetic overflows.
#include <string>

#include <glm/vec3.hpp>

namespace cathbox::vessel {

inline constexpr double kMaxCoordinate_mm = 2000.0;
inline constexpr double kMaxRadius_mm = 100.0;

// Empty when the point is finite and within range; else what is wrong, e.g.
// "x 5.6e+214 mm is outside ±2000 mm". Radii <= 0 are not judged here (readers and the radius
// filter have their own rules for them).
[[nodiscard]] std::string point_range_problem(const glm::dvec3& pos_mm, double radius_mm);

}  // namespace cathbox::vessel
