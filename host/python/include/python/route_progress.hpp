#pragma once
// How far a point still is from the target along a route (the session's centreline from the
// entry to the target): the route length left past the point's closest point on the polyline,
// plus the point's distance off it. The environments' path-length reward is its change per step.
//
//   python::RouteProgress route(scene.route_mm);
//   double left_mm = route.remaining_mm(tip_mm);
#include <span>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::python {

class RouteProgress {
 public:
  RouteProgress() = default;
  explicit RouteProgress(std::span<const glm::vec3> route_mm);
  // 0 for a route of fewer than two points.
  [[nodiscard]] double remaining_mm(const glm::dvec3& point_mm) const;

 private:
  std::vector<glm::dvec3> points_mm_;
  std::vector<double> arc_mm_;  // arc length at each point
};

}  // namespace cathbox::python
