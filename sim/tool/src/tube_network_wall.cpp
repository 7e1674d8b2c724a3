#include "tool/tube_network_wall.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::tool {

namespace {
constexpr double kGridReach_mm = 4.0;  // queries with a larger range fall back to brute force
constexpr std::int64_t kMaxCells = 1 << 21;
}  // namespace

TubeNetworkWall::TubeNetworkWall(std::vector<Tube> tubes, double cell_mm) : tubes_(std::move(tubes)) {
  build(cell_mm);
}

void TubeNetworkWall::add_tube(const Tube& tube) { tubes_.push_back(tube); }

void TubeNetworkWall::add_polyline(const std::vector<glm::dvec3>& points_mm, double radius_mm,
                                   std::int32_t segment) {
  for (std::size_t i = 0; i + 1 < points_mm.size(); ++i) {
    tubes_.push_back(Tube{points_mm[i], points_mm[i + 1], radius_mm, radius_mm, segment});
  }
}

void TubeNetworkWall::build(double cell_mm) {
  cell_start_.clear();
  cell_items_.clear();
  nx_ = ny_ = nz_ = 0;
  if (tubes_.empty()) return;
  reach_ = kGridReach_mm;
  glm::dvec3 lo(std::numeric_limits<double>::max());
  glm::dvec3 hi(-std::numeric_limits<double>::max());
  double max_radius = 0.0;
  for (const Tube& t : tubes_) {
    const double r = std::max(t.radius_a_mm, t.radius_b_mm) + reach_;
    max_radius = std::max(max_radius, r);
    lo = glm::min(lo, glm::min(t.a_mm, t.b_mm) - r);
    hi = glm::max(hi, glm::max(t.a_mm, t.b_mm) + r);
  }
  cell_ = cell_mm > 0.0 ? cell_mm : std::max(1.0, max_radius);
  // Keep the grid bounded whatever the input.
  for (;;) {
    const glm::dvec3 n = glm::ceil((hi - lo) / cell_);
    if (n.x * n.y * n.z <= static_cast<double>(kMaxCells)) {
      nx_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(n.x));
      ny_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(n.y));
      nz_ = std::max<std::int64_t>(1, static_cast<std::int64_t>(n.z));
      break;
    }
    cell_ *= 2.0;
  }
  origin_ = lo;
  const std::size_t cells = static_cast<std::size_t>(nx_ * ny_ * nz_);
  std::vector<std::uint32_t> counts(cells + 1, 0);
  auto for_cells = [&](const Tube& t, auto&& fn) {
    const double r = std::max(t.radius_a_mm, t.radius_b_mm) + reach_;
    const glm::dvec3 a = (glm::min(t.a_mm, t.b_mm) - r - origin_) / cell_;
    const glm::dvec3 b = (glm::max(t.a_mm, t.b_mm) + r - origin_) / cell_;
    const auto clampi = [](double v, std::int64_t n) {
      return std::clamp<std::int64_t>(static_cast<std::int64_t>(std::floor(v)), 0, n - 1);
    };
    for (std::int64_t z = clampi(a.z, nz_); z <= clampi(b.z, nz_); ++z)
      for (std::int64_t y = clampi(a.y, ny_); y <= clampi(b.y, ny_); ++y)
        for (std::int64_t x = clampi(a.x, nx_); x <= clampi(b.x, nx_); ++x)
          fn(static_cast<std::size_t>((z * ny_ + y) * nx_ + x));
  };
  for (const Tube& t : tubes_) for_cells(t, [&](std::size_t c) { ++counts[c + 1]; });
  for (std::size_t c = 0; c < cells; ++c) counts[c + 1] += counts[c];
  cell_start_ = counts;
  cell_items_.assign(counts[cells], 0);
  std::vector<std::uint32_t> fill(counts.begin(), counts.end() - 1);
  for (std::uint32_t i = 0; i < tubes_.size(); ++i) {
    for_cells(tubes_[i], [&](std::size_t c) { cell_items_[fill[c]++] = i; });
  }
}

std::int64_t TubeNetworkWall::cell_of(const glm::dvec3& p) const {
  if (nx_ == 0) return -1;
  const glm::dvec3 g = (p - origin_) / cell_;
  if (!(g.x >= 0.0 && g.y >= 0.0 && g.z >= 0.0)) return -1;  // also rejects NaN
  const auto x = static_cast<std::int64_t>(g.x);
  const auto y = static_cast<std::int64_t>(g.y);
  const auto z = static_cast<std::int64_t>(g.z);
  if (x >= nx_ || y >= ny_ || z >= nz_) return -1;
  return (z * ny_ + y) * nx_ + x;
}

double TubeNetworkWall::depth_in(std::size_t i, const glm::dvec3& p, glm::dvec3& axis_point) const {
  const Tube& t = tubes_[i];
  const glm::dvec3 ab = t.b_mm - t.a_mm;
  const double len2 = glm::dot(ab, ab);
  double u = len2 > 0.0 ? glm::dot(p - t.a_mm, ab) / len2 : 0.0;
  u = std::clamp(u, 0.0, 1.0);
  axis_point = t.a_mm + u * ab;
  const double r = t.radius_a_mm + u * (t.radius_b_mm - t.radius_a_mm);
  return r - glm::length(p - axis_point);
}

template <typename Fn>
void TubeNetworkWall::for_candidates(const glm::dvec3& p, bool use_grid, Fn&& fn) const {
  const std::int64_t c = use_grid ? cell_of(p) : -1;
  if (c >= 0) {
    const std::uint32_t* first = cell_items_.data() + cell_start_[static_cast<std::size_t>(c)];
    const std::uint32_t* last = cell_items_.data() + cell_start_[static_cast<std::size_t>(c) + 1];
    if (first != last) {
      for (const std::uint32_t* it = first; it != last; ++it) fn(static_cast<std::size_t>(*it));
      return;
    }
  }
  for (std::size_t i = 0; i < tubes_.size(); ++i) fn(i);
}

double TubeNetworkWall::deepest(const glm::dvec3& p, bool use_grid, std::size_t& best_i, glm::dvec3& best_axis) const {
  double best = -std::numeric_limits<double>::infinity();
  best_i = 0;
  best_axis = glm::dvec3(0.0);
  for_candidates(p, use_grid, [&](std::size_t i) {
    glm::dvec3 q;
    const double d = depth_in(i, p, q);
    if (d > best) {
      best = d;
      best_i = i;
      best_axis = q;
    }
  });
  return best;
}

// The grid's cell holds every tube whose depth at p is above -kGridReach_mm, and LumenBlend
// weighs none below -LumenBlend::kBand_mm: the cell's candidates are all it needs.
double TubeNetworkWall::lumen_radius_mm(const glm::dvec3& p) const {
  if (tubes_.empty()) return -1.0;
  LumenBlend blend;
  for_candidates(p, true, [&](std::size_t i) {
    glm::dvec3 axis;
    const double depth = depth_in(i, p, axis);
    blend.add(depth, depth + glm::length(p - axis));
  });
  return blend.radius_mm();
}

bool TubeNetworkWall::closest(const glm::dvec3& p, bool use_grid, WallContact& out) const {
  if (tubes_.empty()) return false;
  std::size_t best_i = 0;
  glm::dvec3 best_axis(0.0);
  const double best = deepest(p, use_grid, best_i, best_axis);
  if (!std::isfinite(best)) return false;
  const Tube& t = tubes_[best_i];
  glm::dvec3 radial = p - best_axis;
  const double len = glm::length(radial);
  if (len > 1e-12) {
    radial /= len;
  } else {
    // On the axis: any direction normal to the tube.
    const glm::dvec3 axis = t.b_mm - t.a_mm;
    const glm::dvec3 helper = std::abs(axis.x) < 0.9 * glm::length(axis) ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
    radial = glm::normalize(glm::cross(axis, helper));
  }
  const double r = best + len;
  out.point_mm = best_axis + radial * r;
  out.normal = radial;
  out.distance_mm = best;
  out.segment = t.segment;
  return true;
}

bool TubeNetworkWall::probe(const WallProbe& probe, WallHint& hint, WallContact& out) const {
  const bool grid = probe.range_mm + probe.radius_mm <= reach_;
  if (!closest(probe.center_mm, grid, out)) return false;
  hint.index = static_cast<std::uint32_t>(out.segment);
  return out.distance_mm - probe.radius_mm < probe.range_mm;
}

double TubeNetworkWall::signed_distance(const glm::dvec3& p_mm, std::int32_t* segment) const {
  WallContact c;
  if (!closest(p_mm, false, c)) return -std::numeric_limits<double>::infinity();
  if (segment != nullptr) *segment = c.segment;
  return c.distance_mm;
}

}  // namespace cathbox::tool
