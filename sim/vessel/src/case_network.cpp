#include "case_network.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::vessel::detail {
namespace {

// Centripetal Catmull-Rom point between p1 and p2 (alpha = 0.5), t in [0, 1].
[[nodiscard]] glm::dvec3 catmull_rom(const glm::dvec3& p0, const glm::dvec3& p1, const glm::dvec3& p2,
                                     const glm::dvec3& p3, double t) {
  const auto knot = [](double ti, const glm::dvec3& a, const glm::dvec3& b) {
    return ti + std::sqrt(std::max(glm::length(b - a), 1e-9));
  };
  const double t0 = 0.0;
  const double t1 = knot(t0, p0, p1);
  const double t2 = knot(t1, p1, p2);
  const double t3 = knot(t2, p2, p3);
  const double u = t1 + t * (t2 - t1);
  const glm::dvec3 a1 = (t1 - u) / (t1 - t0) * p0 + (u - t0) / (t1 - t0) * p1;
  const glm::dvec3 a2 = (t2 - u) / (t2 - t1) * p1 + (u - t1) / (t2 - t1) * p2;
  const glm::dvec3 a3 = (t3 - u) / (t3 - t2) * p2 + (u - t2) / (t3 - t2) * p3;
  const glm::dvec3 b1 = (t2 - u) / (t2 - t0) * a1 + (u - t0) / (t2 - t0) * a2;
  const glm::dvec3 b2 = (t3 - u) / (t3 - t1) * a2 + (u - t1) / (t3 - t1) * a3;
  return (t2 - u) / (t2 - t1) * b1 + (u - t1) / (t2 - t1) * b2;
}

}  // namespace

std::int32_t Network::add(const std::string& name, const std::vector<Knot>& knots, std::vector<std::int32_t> parents,
                          double flow, const RadiusProfile& profile, double spacing_radii) {
  Segment s;
  s.id = next_id_++;
  s.name = name;
  s.flow = flow;
  s.parents = parents;
  s.points = sample(knots, profile, spacing_radii > 0.0 ? spacing_radii : spacing_radii_);
  for (std::int32_t p : parents) {
    model_.segments[static_cast<std::size_t>(*model_.index_of(p))].children.push_back(s.id);
  }
  model_.segments.push_back(std::move(s));
  return model_.segments.back().id;
}

std::int32_t Network::add_link(const std::string& name, std::int32_t from, const std::vector<glm::dvec3>& inner,
                               const glm::dvec3& to, double radius_mm, const std::vector<std::int32_t>& into) {
  std::vector<Knot> knots{{end(from), radius_mm}};
  for (const glm::dvec3& p : inner) knots.push_back({p, radius_mm});
  knots.push_back({to, radius_mm});
  const std::int32_t id = add(name, knots, {from});
  for (std::int32_t child : into) {
    model_.segments.back().children.push_back(child);
    model_.segments[static_cast<std::size_t>(*model_.index_of(child))].parents.push_back(id);
  }
  return id;
}

std::vector<CenterlinePoint> Network::sample(const std::vector<Knot>& knots, const RadiusProfile& profile,
                                             double spacing_radii) const {
  // Dense polyline through the knots (end knots duplicated for the spline's end tangents).
  std::vector<glm::dvec3> dense;
  std::vector<double> dense_radius;
  const std::size_t n = knots.size();
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const glm::dvec3 p0 = i == 0 ? 2.0 * knots[0].pos_mm - knots[1].pos_mm : knots[i - 1].pos_mm;
    const glm::dvec3 p3 = i + 2 < n ? knots[i + 2].pos_mm : 2.0 * knots[n - 1].pos_mm - knots[n - 2].pos_mm;
    constexpr int kSteps = 48;
    for (int k = 0; k < kSteps; ++k) {
      const double t = static_cast<double>(k) / kSteps;
      dense.push_back(catmull_rom(p0, knots[i].pos_mm, knots[i + 1].pos_mm, p3, t));
      dense_radius.push_back(knots[i].radius_mm + t * (knots[i + 1].radius_mm - knots[i].radius_mm));
    }
  }
  dense.push_back(knots.back().pos_mm);
  dense_radius.push_back(knots.back().radius_mm);
  std::vector<double> arc(dense.size(), 0.0);
  for (std::size_t i = 1; i < dense.size(); ++i) arc[i] = arc[i - 1] + glm::length(dense[i] - dense[i - 1]);
  const double length = arc.back();
  const auto at = [&](double s) {
    const auto it = std::upper_bound(arc.begin(), arc.end(), s);
    std::size_t j = it == arc.begin() ? 0 : static_cast<std::size_t>(it - arc.begin()) - 1;
    j = std::min(j, arc.size() - 2);
    const double span = arc[j + 1] - arc[j];
    const double a = span > 0.0 ? std::clamp((s - arc[j]) / span, 0.0, 1.0) : 0.0;
    CenterlinePoint p;
    p.pos_mm = dense[j] + a * (dense[j + 1] - dense[j]);
    p.radius_mm = dense_radius[j] + a * (dense_radius[j + 1] - dense_radius[j]);
    if (profile) p.radius_mm = profile(s, length, p.radius_mm);
    return p;
  };
  // Curvature of the dense polyline (turning angle per length), to sample bends densely.
  std::vector<double> curvature(dense.size(), 0.0);
  for (std::size_t i = 1; i + 1 < dense.size(); ++i) {
    const glm::dvec3 a = dense[i] - dense[i - 1];
    const glm::dvec3 b = dense[i + 1] - dense[i];
    const double la = glm::length(a);
    const double lb = glm::length(b);
    if (la > 0.0 && lb > 0.0) {
      const double c = std::clamp(glm::dot(a, b) / (la * lb), -1.0, 1.0);
      curvature[i] = std::acos(c) / (0.5 * (la + lb));
    }
  }
  const auto curvature_at = [&](double s) {
    const auto it = std::upper_bound(arc.begin(), arc.end(), s);
    return curvature[std::min(static_cast<std::size_t>(it - arc.begin()), curvature.size() - 1)];
  };
  // Points about spacing_radii local radii apart (at most 0.3 bend radii in bends), placed at
  // the same relative positions along the curve, at least 3.
  std::vector<double> stations{0.0};
  for (double s = 0.0; s < length;) {
    double h = std::max(0.3, spacing_radii * at(s).radius_mm);
    const double kappa = curvature_at(s);
    if (kappa > 0.0) h = std::max(0.3, std::min(h, 0.3 / kappa));
    s += h;
    stations.push_back(std::min(s, length));
  }
  const double overshoot = stations.back() - stations[stations.size() - 2];
  if (stations.size() > 2 && overshoot < 0.5 * (stations[stations.size() - 2] - stations[stations.size() - 3])) {
    stations.erase(stations.end() - 2);  // merge a sliver at the end
  }
  while (stations.size() < 3) stations.insert(stations.end() - 1, 0.5 * (stations[stations.size() - 2] + stations.back()));
  const double scale = length / stations.back();
  std::vector<CenterlinePoint> points;
  for (double station : stations) points.push_back(at(station * scale));
  points.front().pos_mm = knots.front().pos_mm;
  points.back().pos_mm = knots.back().pos_mm;
  return points;
}

}  // namespace cathbox::vessel::detail
