#include "centerline_polyline.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

namespace cathbox::vessel::detail {
namespace {

// The span j (points j, j+1) holding arc t and the fraction a of the way along it.
struct Span {
  std::size_t j = 0;
  double a = 0.0;
};

[[nodiscard]] Span locate(const Polyline& pl, double t) {
  t = std::clamp(t, 0.0, pl.length);
  const auto it = std::upper_bound(pl.arc.begin(), pl.arc.end(), t);
  std::size_t j = it == pl.arc.begin() ? 0 : static_cast<std::size_t>(it - pl.arc.begin()) - 1;
  j = std::min(j, pl.arc.size() - 2);
  const double span = pl.arc[j + 1] - pl.arc[j];
  return {j, span > 0.0 ? std::clamp((t - pl.arc[j]) / span, 0.0, 1.0) : 0.0};
}

}  // namespace

Polyline make_polyline(const Segment& s) {
  Polyline pl;
  const std::size_t n = s.points.size();
  for (const CenterlinePoint& p : s.points) {
    pl.pos.push_back(p.pos_mm);
    pl.radius.push_back(p.radius_mm);
  }
  pl.arc.assign(n, 0.0);
  pl.edge_dir.assign(n > 1 ? n - 1 : 0, glm::dvec3(0.0));
  for (std::size_t j = 0; j + 1 < n; ++j) {
    const glm::dvec3 d = pl.pos[j + 1] - pl.pos[j];
    const double len = glm::length(d);
    pl.arc[j + 1] = pl.arc[j] + len;
    if (len > 1e-12) pl.edge_dir[j] = d / len;
  }
  pl.length = n > 0 ? pl.arc.back() : 0.0;
  // Zero-length edges borrow a neighbour's direction.
  for (std::size_t j = 1; j < pl.edge_dir.size(); ++j) {
    if (glm::length(pl.edge_dir[j]) == 0.0) pl.edge_dir[j] = pl.edge_dir[j - 1];
  }
  for (std::size_t j = pl.edge_dir.size(); j-- > 1;) {
    if (glm::length(pl.edge_dir[j - 1]) == 0.0) pl.edge_dir[j - 1] = pl.edge_dir[j];
  }
  pl.tangent.assign(n, glm::dvec3(0.0, 0.0, 1.0));
  for (std::size_t j = 0; j < n && !pl.edge_dir.empty(); ++j) {
    const glm::dvec3 in = pl.edge_dir[j == 0 ? 0 : j - 1];
    const glm::dvec3 out = pl.edge_dir[std::min(j, pl.edge_dir.size() - 1)];
    const glm::dvec3 sum = in + out;
    pl.tangent[j] = glm::length(sum) > 1e-9 ? glm::normalize(sum) : out;
  }
  return pl;
}

Sample sample(const Polyline& pl, double t) {
  const auto [j, a] = locate(pl, t);
  Sample s;
  // Between points the centre follows a Catmull-Rom curve, so rings placed between the points
  // (trimmed segments) sit on a smooth curve through them rather than on its chords.
  const std::size_t n = pl.pos.size();
  const glm::dvec3 p0 = j > 0 ? pl.pos[j - 1] : 2.0 * pl.pos[0] - pl.pos[1];
  const glm::dvec3 p3 = j + 2 < n ? pl.pos[j + 2] : 2.0 * pl.pos[n - 1] - pl.pos[n - 2];
  const glm::dvec3& p1 = pl.pos[j];
  const glm::dvec3& p2 = pl.pos[j + 1];
  s.pos = 0.5 * (2.0 * p1 + (p2 - p0) * a + (2.0 * p0 - 5.0 * p1 + 4.0 * p2 - p3) * a * a +
                 (3.0 * p1 - p0 - 3.0 * p2 + p3) * a * a * a);
  s.radius = pl.radius[j] + a * (pl.radius[j + 1] - pl.radius[j]);
  const glm::dvec3 tan = pl.tangent[j] + a * (pl.tangent[j + 1] - pl.tangent[j]);
  s.tangent = glm::length(tan) > 1e-9 ? glm::normalize(tan) : pl.edge_dir[j];
  return s;
}

double sample_radius(const Polyline& pl, double t) {
  const auto [j, a] = locate(pl, t);
  return pl.radius[j] + a * (pl.radius[j + 1] - pl.radius[j]);
}

}  // namespace cathbox::vessel::detail
