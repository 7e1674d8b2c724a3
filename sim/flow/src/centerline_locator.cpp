#include "flow/centerline_locator.hpp"

#include <algorithm>
#include <limits>

#include <glm/geometric.hpp>

#include "lumen.hpp"

namespace cathbox::flow {

CenterlineLocator::CenterlineLocator(const vessel::VesselModel& model) : model_(&model) {
  arcs_.reserve(model.segments.size());
  for (const vessel::Segment& s : model.segments) arcs_.push_back(point_arcs_mm(s));
}

CenterlinePosition CenterlineLocator::nearest(const glm::dvec3& p) const {
  CenterlinePosition best;
  best.distance_mm = std::numeric_limits<double>::infinity();
  for (std::uint32_t si = 0; si < model_->segments.size(); ++si) {
    if (const CenterlinePosition at = nearest_on(si, p); at.distance_mm < best.distance_mm) best = at;
  }
  return best;
}

CenterlinePosition CenterlineLocator::nearest_on(std::uint32_t segment, const glm::dvec3& p) const {
  CenterlinePosition best;
  best.segment = segment;
  double best_d2 = std::numeric_limits<double>::infinity();
  const vessel::Segment& s = model_->segments[segment];
  for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
    const glm::dvec3 a = s.points[i].pos_mm;
    const glm::dvec3 ab = s.points[i + 1].pos_mm - a;
    const double len2 = glm::dot(ab, ab);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec3 d = a + t * ab - p;
    const double d2 = glm::dot(d, d);
    if (d2 < best_d2) {
      best_d2 = d2;
      best.arc_mm = arcs_[segment][i] + t * (arcs_[segment][i + 1] - arcs_[segment][i]);
    }
  }
  best.distance_mm = std::sqrt(best_d2);
  return best;
}

glm::dvec3 CenterlineLocator::point_at(std::uint32_t segment, double arc_mm) const {
  const vessel::Segment& s = model_->segments[segment];
  const ArcPiece p = piece_at(arcs_[segment], arc_mm);
  return s.points[p.j].pos_mm + p.t * (s.points[p.j + 1].pos_mm - s.points[p.j].pos_mm);
}

double CenterlineLocator::radius_at(std::uint32_t segment, double arc_mm) const {
  return radius_at_mm(model_->segments[segment], arcs_[segment], arc_mm);
}

}  // namespace cathbox::flow
