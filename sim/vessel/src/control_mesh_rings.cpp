// The control mesh's rings: placed along each segment between its trimmed ends, corrected for
// the subdivision's axial shrink, and their frames propagated without twist.
#include <algorithm>
#include <cmath>
#include <deque>
#include <numbers>

#include <glm/geometric.hpp>

#include "control_mesh_steps.hpp"
#include "ring_arcs.hpp"
#include "vessel/rotation_minimizing_frame.hpp"

namespace cathbox::vessel::detail {
namespace {

constexpr double kMinControlRadius = 0.25;  // solved control radius, at least this of the target

// c with c[0] = t[0], c[n-1] = t[n-1] and (c[j-1] + 4 c[j] + c[j+1]) / 6 = t[j] inside
// (Thomas algorithm; the system is diagonally dominant, so no pivoting is needed).
template <class T>
void solve_bspline_average(const std::vector<T>& t, std::vector<T>& c) {
  const std::size_t n = t.size();
  c = t;
  if (n < 3) return;
  std::vector<double> upper(n, 0.0);  // modified super-diagonal
  // Rows j = 1..n-2: (1/6) c[j-1] + (4/6) c[j] + (1/6) c[j+1] = t[j].
  T rhs_prev{};
  double upper_prev = 0.0;
  for (std::size_t j = 1; j + 1 < n; ++j) {
    T rhs = 6.0 * t[j];
    if (j == 1) rhs -= t[0];
    if (j + 2 == n) rhs -= t[n - 1];
    const double lower = j == 1 ? 0.0 : 1.0;
    const double denom = 4.0 - lower * upper_prev;
    upper[j] = (j + 2 == n) ? 0.0 : 1.0 / denom;
    rhs = (rhs - lower * rhs_prev) / denom;
    c[j] = rhs;
    rhs_prev = rhs;
    upper_prev = upper[j];
  }
  for (std::size_t j = n - 2; j-- > 1;) c[j] -= upper[j] * c[j + 1];
}

}  // namespace

void ControlMeshBuilder::reserve_mesh() {
  const std::size_t m = static_cast<std::size_t>(m_);
  const std::size_t points = model_.point_count();
  const std::size_t caps = options_.caps ? graph_.free_ends().size() : 0;
  std::size_t junction_ends = 0;
  for (const Junction& junction : graph_.junctions()) junction_ends += junction.ends.size();
  const std::size_t faces = (points - model_.segments.size() + caps + junction_ends) * m + caps;
  mesh_.rings.reserve(points);
  mesh_.segment_first_ring.reserve(model_.segments.size() + 1);
  mesh_.positions_mm.reserve((points + caps) * m);
  mesh_.face_sizes.reserve(faces);
  mesh_.face_regions.reserve(faces);
  mesh_.face_vertices.reserve(4 * faces);
  ring_cos_.resize(m);
  ring_sin_.resize(m);
  for (int k = 0; k < m_; ++k) {
    const double angle = 2.0 * std::numbers::pi * k / m_;
    ring_cos_[static_cast<std::size_t>(k)] = std::cos(angle);
    ring_sin_[static_cast<std::size_t>(k)] = std::sin(angle);
  }
}

void ControlMeshBuilder::place_rings() {
  std::vector<double> arcs;
  for (std::size_t s = 0; s < model_.segments.size(); ++s) {
    const Polyline& pl = polylines_[s];
    mesh_.segment_first_ring.push_back(static_cast<std::uint32_t>(mesh_.rings.size()));
    ring_arcs(pl, trims_[2 * s], pl.length - trims_[2 * s + 1], arcs);
    for (double t : arcs) {
      const Sample smp = sample(pl, t);
      Ring ring;
      ring.segment = static_cast<std::uint32_t>(s);
      ring.center_mm = smp.pos;
      ring.tangent = smp.tangent;
      ring.radius_mm = smp.radius;
      ring.control_radius_mm = smp.radius / ratio_;
      ring.arc_mm = t;
      mesh_.rings.push_back(ring);
    }
    if (options_.compensate_shrink) correct_axial_shrink(mesh_.segment_first_ring.back(), mesh_.rings.size());
  }
  mesh_.segment_first_ring.push_back(static_cast<std::uint32_t>(mesh_.rings.size()));
}

void ControlMeshBuilder::ring_arcs(const Polyline& pl, double a, double b, std::vector<double>& arcs) const {
  arcs.clear();
  if (options_.ring_placement == RingPlacement::kPerPoint) {
    for (double arc : pl.arc) arcs.push_back(a + (arc / pl.length) * (b - a));
    return;
  }
  detail::adaptive_ring_arcs(pl, a, b, arcs);
}

void ControlMeshBuilder::correct_axial_shrink(std::size_t begin, std::size_t end) {
  const std::size_t n = end - begin;
  if (n < 3) return;
  target_c_.resize(n);
  target_r_.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    target_c_[j] = mesh_.rings[begin + j].center_mm;
    target_r_[j] = mesh_.rings[begin + j].control_radius_mm;
  }
  solve_bspline_average(target_c_, solved_c_);
  solve_bspline_average(target_r_, solved_r_);
  for (std::size_t j = 1; j + 1 < n; ++j) {
    // In a bend each ring point is pulled towards the centre of curvature by its own distance
    // from it times alpha^2 / 6 (alpha: turning angle per ring); moving the centre makes up for
    // the centre's share only, so the radius gets the rest.
    const double cos_2a = std::clamp(glm::dot(mesh_.rings[begin + j - 1].tangent, mesh_.rings[begin + j + 1].tangent), -1.0, 1.0);
    const double alpha = 0.5 * std::acos(cos_2a);
    mesh_.rings[begin + j].center_mm = solved_c_[j];
    mesh_.rings[begin + j].control_radius_mm =
        std::max(kMinControlRadius * target_r_[j], solved_r_[j]) * (1.0 + alpha * alpha / 6.0);
  }
}

[[nodiscard]] std::size_t ControlMeshBuilder::end_ring(const SegmentEnd& e) const {
  return e.at_end ? mesh_.segment_first_ring[e.segment + 1] - 1 : mesh_.segment_first_ring[e.segment];
}

void ControlMeshBuilder::propagate_segment(std::uint32_t s, bool from_end, const glm::dvec3& normal) {
  const std::size_t first = mesh_.segment_first_ring[s];
  const std::size_t last = mesh_.segment_first_ring[s + 1] - 1;
  const auto travel = [&](const Ring& r) { return from_end ? -r.tangent : r.tangent; };
  std::size_t cur = from_end ? last : first;
  Ring* prev = &mesh_.rings[cur];
  prev->normal = glm::normalize(normal - glm::dot(normal, prev->tangent) * prev->tangent);
  prev->binormal = glm::cross(prev->tangent, prev->normal);
  while (cur != (from_end ? first : last)) {
    cur = from_end ? cur - 1 : cur + 1;
    Ring& ring = mesh_.rings[cur];
    ring.normal = transport_normal(prev->center_mm, travel(*prev), prev->normal, ring.center_mm, travel(ring));
    ring.binormal = glm::cross(ring.tangent, ring.normal);
    prev = &ring;
  }
}

void ControlMeshBuilder::propagate_frames() {
  const std::size_t n = model_.segments.size();
  std::vector<char> done(n, 0);
  std::deque<std::uint32_t> queue;
  const auto visit_from = [&](std::uint32_t s) {
    for (bool at_end : {false, true}) {
      const int j = graph_.junction_of(s, at_end);
      if (j < 0) continue;
      const Junction& junction = graph_.junctions()[static_cast<std::size_t>(j)];
      const Ring& a = mesh_.rings[end_ring({s, at_end})];
      const glm::dvec3 into = at_end ? a.tangent : -a.tangent;  // travel towards the junction
      for (const SegmentEnd& e : junction.ends) {
        if (done[e.segment]) continue;
        const Ring& b = mesh_.rings[end_ring(e)];
        const glm::dvec3 away = e.at_end ? -b.tangent : b.tangent;
        glm::dvec3 mid = into + away;
        mid = glm::length(mid) > 1e-9 ? glm::normalize(mid) : into;
        const glm::dvec3 at_center = transport_normal(a.center_mm, into, a.normal, junction.center_mm, mid);
        const glm::dvec3 normal = transport_normal(junction.center_mm, mid, at_center, b.center_mm, away);
        propagate_segment(e.segment, e.at_end, normal);
        done[e.segment] = 1;
        queue.push_back(e.segment);
      }
    }
  };
  for (int pass = 0; pass < 2; ++pass) {
    for (std::uint32_t s = 0; s < n; ++s) {
      // Roots first: segments without parents, then anything left (pure cycles).
      if (done[s] || (pass == 0 && !model_.segments[s].parents.empty())) continue;
      const Ring& first = mesh_.rings[mesh_.segment_first_ring[s]];
      propagate_segment(s, false, any_perpendicular(first.tangent));
      done[s] = 1;
      queue.push_back(s);
      while (!queue.empty()) {
        const std::uint32_t cur = queue.front();
        queue.pop_front();
        visit_from(cur);
      }
    }
  }
}

}  // namespace cathbox::vessel::detail
