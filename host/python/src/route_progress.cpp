#include "python/route_progress.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::python {

RouteProgress::RouteProgress(std::span<const glm::vec3> route_mm) {
  double arc = 0.0;
  for (const glm::vec3& p : route_mm) {
    const glm::dvec3 q(p);
    if (!points_mm_.empty()) arc += glm::length(q - points_mm_.back());
    points_mm_.push_back(q);
    arc_mm_.push_back(arc);
  }
}

double RouteProgress::remaining_mm(const glm::dvec3& point_mm) const {
  if (points_mm_.size() < 2) return 0.0;
  double best_d2 = std::numeric_limits<double>::infinity();
  double best_arc = 0.0;
  for (std::size_t i = 0; i + 1 < points_mm_.size(); ++i) {
    const glm::dvec3 a = points_mm_[i];
    const glm::dvec3 ab = points_mm_[i + 1] - a;
    const double t = std::clamp(glm::dot(point_mm - a, ab) / std::max(glm::dot(ab, ab), 1e-12), 0.0, 1.0);
    const glm::dvec3 off = point_mm - (a + t * ab);
    const double d2 = glm::dot(off, off);
    if (d2 < best_d2) {  // the first closest segment, as numpy's argmin
      best_d2 = d2;
      best_arc = arc_mm_[i] + t * (arc_mm_[i + 1] - arc_mm_[i]);
    }
  }
  return arc_mm_.back() - best_arc + std::sqrt(best_d2);
}

}  // namespace cathbox::python
