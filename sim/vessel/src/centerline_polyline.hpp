#pragma once
// The smoothed centerline of one segment as the control mesh builder and the junction fit see
// it: points with arc length and bisected tangents, the centre between points on a Catmull-Rom
// curve through them, the radius linear between them.
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/segment.hpp"

namespace cathbox::vessel::detail {

struct Polyline {
  std::vector<glm::dvec3> pos;
  std::vector<double> radius;
  std::vector<double> arc;
  std::vector<glm::dvec3> tangent;  // thesis: end points use the end edge, inner points bisect
  std::vector<glm::dvec3> edge_dir;
  double length = 0.0;
};

struct Sample {
  glm::dvec3 pos{0.0};
  glm::dvec3 tangent{0.0, 0.0, 1.0};
  double radius = 0.0;
};

[[nodiscard]] Polyline make_polyline(const Segment& s);
// The centreline at arc t (clamped to [0, length]); needs at least two points.
[[nodiscard]] Sample sample(const Polyline& pl, double t);
// The radius at arc t only (linear between points).
[[nodiscard]] double sample_radius(const Polyline& pl, double t);

}  // namespace cathbox::vessel::detail
