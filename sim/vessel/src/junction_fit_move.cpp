#include "junction_fit_move.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::vessel::detail {
namespace {

// The nearest point of the axis polyline: the nearest sample (every kCoarseStride-th sample,
// then those around the best of them; the axis is a smooth curve a few radii long sampled every
// half radius, so its distance to a point has one minimum within that window), then the two
// pieces beside it.
[[nodiscard]] Nearest nearest_on(const JunctionFit::Axis& axis, const glm::dvec3& p, double scale) {
  constexpr std::size_t kCoarseStride = 3;
  const std::size_t n = axis.pos.size();
  std::size_t near = 0;
  double near_d2 = std::numeric_limits<double>::infinity();
  const auto consider = [&](std::size_t i) {
    const glm::dvec3 d = p - axis.pos[i];
    const double d2 = glm::dot(d, d);
    if (d2 < near_d2) {
      near_d2 = d2;
      near = i;
    }
  };
  for (std::size_t i = 0; i < n; i += kCoarseStride) consider(i);
  consider(n - 1);
  const std::size_t coarse = near;
  for (std::size_t i = coarse > kCoarseStride ? coarse - kCoarseStride : 0; i <= std::min(n - 1, coarse + kCoarseStride); ++i) consider(i);
  Nearest best;
  double best_d2 = std::numeric_limits<double>::infinity();
  glm::dvec3 best_foot = axis.pos[near];
  const std::size_t from = near > 0 ? near - 1 : 0;
  const std::size_t to = std::min(near + 1, n - 1);
  for (std::size_t i = from; i < to; ++i) {
    const glm::dvec3 a = axis.pos[i];
    const glm::dvec3 d = axis.pos[i + 1] - a;
    const double len2 = glm::dot(d, d);
    const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
    const glm::dvec3 foot = a + t * d;
    const double d2 = glm::dot(p - foot, p - foot);
    if (d2 < best_d2) {
      best_d2 = d2;
      best_foot = foot;
      best.radius = scale * (axis.radius[i] + t * (axis.radius[i + 1] - axis.radius[i]));
      best.arc = axis.step * (static_cast<double>(i) + t);
    }
  }
  if (n == 1) best.radius = scale * axis.radius[0];
  const double dist = std::sqrt(std::min(best_d2, near_d2));
  if (dist > 0.0) best.direction = (p - best_foot) / dist;
  best.signed_distance = dist - best.radius;
  return best;
}

[[nodiscard]] double smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3.0 - 2.0 * x);
}

// The nearest point of every tube that can matter to a point `at`: axes in order of a lower
// bound of their distance; one whose tube is certainly further than the nearest so far plus the
// blend width (and cannot hold the point) changes nothing and is skipped (its distance stays
// infinite). `branch`: the vertex's own branch, always searched (-1: none).
void nearest_tubes(const std::vector<JunctionFit::Axis>& axes, int branch, const glm::dvec3& at, TubeSearch& search) {
  search.order.clear();
  double largest_radius = 0.0;
  for (std::size_t b = 0; b < axes.size(); ++b) {
    search.order.emplace_back(std::max(0.0, glm::length(at - axes[b].bound_center) - axes[b].bound_radius), b);
    largest_radius = std::max(largest_radius, axes[b].max_radius);
  }
  std::sort(search.order.begin(), search.order.end());
  search.nearest.assign(axes.size(), Nearest{});
  double nearest_abs = std::numeric_limits<double>::infinity();
  for (const auto& [lower_bound, b] : search.order) {
    const bool needed = static_cast<int>(b) == branch || lower_bound <= axes[b].max_radius ||
                        lower_bound - axes[b].max_radius < nearest_abs + kFitBlendRadii * largest_radius;
    if (!needed) continue;
    search.nearest[b] = nearest_on(axes[b], at, 1.0);
    nearest_abs = std::min(nearest_abs, std::abs(search.nearest[b].signed_distance));
  }
}

}  // namespace

std::optional<FitMove> fit_move(const std::vector<JunctionFit::Axis>& axes, int branch, const glm::dvec3& at,
                                TubeSearch& search) {
  nearest_tubes(axes, branch, at, search);
  const std::vector<Nearest>& nearest = search.nearest;
  // The nearest and second nearest tube surfaces (by distance, inside or out).
  std::array<Nearest, 2> best;
  Nearest own;
  bool inside_other = false;
  std::size_t first_index = 0;
  for (std::size_t b = 0; b < nearest.size(); ++b) {
    if (static_cast<int>(b) == branch) own = nearest[b];
    if (std::abs(nearest[b].signed_distance) < std::abs(nearest[first_index].signed_distance)) first_index = b;
  }
  best[0] = nearest[first_index];
  for (std::size_t b = 0; b < nearest.size(); ++b) {
    if (b == first_index) continue;
    if (std::abs(nearest[b].signed_distance) < std::abs(best[1].signed_distance)) best[1] = nearest[b];
    inside_other = inside_other || nearest[b].signed_distance < -kFitInsideRadii * nearest[b].radius;
  }
  const Nearest& first = best[0];
  const Nearest& second = best[1];
  // A point inside another branch's tube is inside the lumen the branches share: left alone.
  if (inside_other || !(first.radius > 0.0) || glm::dot(first.direction, first.direction) == 0.0) return std::nullopt;
  const bool outside_both = first.signed_distance > -kFitInsideRadii * first.radius &&
                            second.signed_distance > -kFitInsideRadii * second.radius;
  const double side = std::max(
      smoothstep((std::abs(second.signed_distance) - std::abs(first.signed_distance)) / (kFitBlendRadii * first.radius)),
      outside_both ? smoothstep((glm::dot(first.direction, second.direction) - kFitSameSide) / (1.0 - kFitSameSide)) : 0.0);
  const double near = 1.0 - smoothstep((std::abs(first.signed_distance) - kFitFullRadii * first.radius) /
                                       ((kFitMaxMoveRadii - kFitFullRadii) * first.radius));
  double w = side * near;
  if (branch >= 0) {
    const JunctionFit::Axis& axis = axes[static_cast<std::size_t>(branch)];
    w *= 1.0 - smoothstep((own.arc - axis.trim) / (kFitTubeFadeRadii * axis.ring_radius));
  }
  if (w <= 0.0) return std::nullopt;
  return FitMove{-w * first.signed_distance, first.direction};
}

}  // namespace cathbox::vessel::detail
