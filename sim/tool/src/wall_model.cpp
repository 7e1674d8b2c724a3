#include "tool/wall_model.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {
thread_local int t_probe_pool = 0;
}  // namespace

int probe_pool() { return t_probe_pool; }

ProbePoolScope::ProbePoolScope(int pool) : before_(t_probe_pool) { t_probe_pool = pool; }

ProbePoolScope::~ProbePoolScope() { t_probe_pool = before_; }

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

void LumenBlend::add(double depth_mm, double radius_mm) {
  added_ = true;
  deepest_mm_ = std::max(deepest_mm_, depth_mm);
  if (!(depth_mm > floor_mm())) return;
  if (count_ == kHeld && more_.empty()) {
    // Drop the held tubes that no longer weigh, in order.
    const double floor = floor_mm();
    count_ = static_cast<std::size_t>(std::remove_if(held_.begin(), held_.begin() + static_cast<std::ptrdiff_t>(count_),
                                                     [floor](const Held& h) { return !(h.depth_mm > floor); }) -
                                      held_.begin());
  }
  if (count_ < kHeld && more_.empty()) {
    held_[count_++] = {depth_mm, radius_mm};
  } else {
    more_.push_back({depth_mm, radius_mm});
  }
}

double LumenBlend::radius_mm() const {
  if (!added_) return -1.0;
  const double band = std::max(deepest_mm_, kBand_mm);
  double sum_w = 0.0;
  double sum_wr = 0.0;
  const auto weigh = [&](const Held& h) {
    const double lift = h.depth_mm - deepest_mm_ + band;
    if (!(lift > 0.0)) return;
    sum_w += lift * lift;
    sum_wr += lift * lift * h.radius_mm;
  };
  std::for_each(held_.begin(), held_.begin() + static_cast<std::ptrdiff_t>(count_), weigh);
  std::for_each(more_.begin(), more_.end(), weigh);
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
