#include "tool/wall_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::tool {

CentrelineFoot nearest_on_centreline(const vessel::Segment& s, const glm::dvec3& p) {
  CentrelineFoot best{std::numeric_limits<double>::infinity(), 0, 0.0};
  for (std::size_t i = 0; i + 1 < s.points.size(); ++i) {
    const glm::dvec3 a = s.points[i].pos_mm;
    const glm::dvec3 d = s.points[i + 1].pos_mm - a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec3 q = a + t * d;
    const double d2 = glm::dot(p - q, p - q);
    if (d2 < best.distance2_mm2) best = {d2, i, t};
  }
  if (s.points.size() == 1) best = {glm::dot(p - s.points[0].pos_mm, p - s.points[0].pos_mm), 0, 0.0};
  return best;
}

double LumenBlend::radius_mm() const {
  if (tubes_.empty()) return -1.0;
  double deepest = -std::numeric_limits<double>::infinity();
  for (const auto& [depth, radius] : tubes_) deepest = std::max(deepest, depth);
  const double band = std::max(deepest, kBand_mm);
  double sum_w = 0.0;
  double sum_wr = 0.0;
  for (const auto& [depth, radius] : tubes_) {
    const double lift = depth - deepest + band;
    if (!(lift > 0.0)) continue;
    sum_w += lift * lift;
    sum_wr += lift * lift * radius;
  }
  return sum_w > 0.0 ? sum_wr / sum_w : -1.0;
}

double centreline_radius_mm(const vessel::VesselModel& model, const glm::dvec3& p) {
  LumenBlend blend;
  for (const vessel::Segment& s : model.segments) {
    if (s.points.empty()) continue;
    const CentrelineFoot f = nearest_on_centreline(s, p);
    const double r0 = s.points[f.piece].radius_mm;
    const double r = f.piece + 1 < s.points.size() ? r0 + f.t * (s.points[f.piece + 1].radius_mm - r0) : r0;
    blend.add(r - std::sqrt(f.distance2_mm2), r);
  }
  return blend.radius_mm();
}

double WallModel::lumen_radius_mm(const glm::dvec3& point_mm) const {
  const std::shared_ptr<const WallSurface> s = surface();
  if (!s || s->model.segments.empty()) return -1.0;
  return centreline_radius_mm(s->model, point_mm);
}

}  // namespace cathbox::tool
