#include "vessel/control_mesh_builder.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include <glm/geometric.hpp>

#include "centerline_polyline.hpp"
#include "junction_patch.hpp"
#include "ring_arcs.hpp"
#include "vessel/point_range.hpp"
#include "vessel/rotation_minimizing_frame.hpp"

namespace cathbox::vessel {
namespace {

using detail::Polyline;
using detail::Sample;
using detail::make_polyline;
using detail::sample;
using detail::sample_radius;

constexpr double kPi = 3.14159265358979323846;
constexpr double kInitialTrimRadii = 1.0;   // first guess of a junction ring's distance, in radii
constexpr double kTrimStepRadii = 0.2;      // step when rings still overlap
constexpr double kPlaneMarginRadii = 0.15;  // how far behind another ring's plane a ring must be
constexpr double kCapOffsetRadii = 0.5;     // cap ring distance beyond the free end
constexpr double kCapRingScale = 0.6;       // cap ring radius / end ring radius
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

[[nodiscard]] std::string junction_name(const VesselModel& model, const Junction& junction, std::size_t index) {
  std::string out = "junction " + std::to_string(index) + " (segments";
  for (const SegmentEnd& e : junction.ends) out += " " + std::to_string(model.segments[e.segment].id);
  return out + ")";
}

class Builder {
 public:
  Builder(const VesselModel& model, const VesselGraph& graph, const MeshOptions& options)
      : model_(model), graph_(graph), options_(options), m_(options.ring_points) {}

  ControlMeshResult run() {
    if (m_ < 3 || m_ > 256) return base::Error{"ring size must be between 3 and 256, got " + std::to_string(m_)};
    if (options_.smoothing_passes < 0) return base::Error{"smoothing passes must be >= 0"};
    ratio_ = options_.compensate_shrink ? tube_shrink_ratio(m_) : 1.0;
    for (const Segment& s : model_.segments) {
      // Every later cast and count assumes finite, physical numbers: a model that did not come
      // through a reader (which checks them) is refused here, never meshed into undefined values.
      for (std::size_t k = 0; k < s.points.size(); ++k) {
        if (std::string problem = point_range_problem(s.points[k].pos_mm, s.points[k].radius_mm); !problem.empty()) {
          return base::Error{"segment " + std::to_string(s.id) + " point " + std::to_string(k) + ": " + problem};
        }
      }
      polylines_.push_back(make_polyline(s));
      if (s.points.size() < 2 || !(polylines_.back().length > 0.0)) {
        return base::Error{"segment " + std::to_string(s.id) + " has zero length"};
      }
    }
    trims_.assign(2 * model_.segments.size(), 0.0);
    if (options_.trim_at_junctions) compute_trims();
    reserve_mesh();
    place_rings();
    propagate_frames();
    emit_vertices();
    emit_tubes();
    if (options_.caps) emit_caps();
    if (std::string e = emit_junctions(); !e.empty()) return base::Error{std::move(e)};
    return ControlMeshResult(std::move(mesh_));
  }

 private:
  [[nodiscard]] double end_arc(const SegmentEnd& e, double trim) const {
    return e.at_end ? polylines_[e.segment].length - trim : trim;
  }

  // Two passes: every junction first keeps to its share of each segment; those still
  // overlapping may then use what the segment's other end left over.
  void compute_trims() {
    std::vector<char> settled(graph_.junctions().size(), 0);
    for (int pass = 0; pass < 2; ++pass) {
      for (std::size_t j = 0; j < graph_.junctions().size(); ++j) {
        if (!settled[j]) settled[j] = trim_junction(graph_.junctions()[j], pass == 1) ? 1 : 0;
      }
    }
  }

  // Moves the junction's rings out along their segments until each ring lies behind the plane
  // of every other ring there. Returns false if a segment ran out of length first.
  bool trim_junction(const Junction& junction, bool relaxed) {
    const std::size_t k = junction.ends.size();
    std::vector<double> d(k);
    std::vector<double> max_d(k);
    for (std::size_t i = 0; i < k; ++i) {
      max_d[i] = trim_limit(junction, junction.ends[i], relaxed);
      const SegmentEnd& e = junction.ends[i];
      const double r = sample(polylines_[e.segment], end_arc(e, 0.0)).radius / ratio_;
      d[i] = std::min(std::max(kInitialTrimRadii * r, trims_[2 * e.segment + (e.at_end ? 1 : 0)]), max_d[i]);
    }
    std::vector<Sample> at(k);
    std::vector<glm::dvec3> out_normal(k);
    bool clear = false;
    for (int iteration = 0; iteration < 400 && !clear; ++iteration) {
      for (std::size_t i = 0; i < k; ++i) {
        const SegmentEnd& e = junction.ends[i];
        at[i] = sample(polylines_[e.segment], end_arc(e, d[i]));
        out_normal[i] = e.at_end ? -at[i].tangent : at[i].tangent;
      }
      clear = true;
      bool changed = false;
      for (std::size_t i = 0; i < k; ++i) {
        if (!ring_in_front(at, out_normal, i)) continue;
        // A ring reaches in front of ring i's plane: move ring i further out.
        clear = false;
        if (d[i] < max_d[i]) {
          d[i] = std::min(max_d[i], d[i] + kTrimStepRadii * at[i].radius / ratio_);
          changed = true;
        }
      }
      if (!changed) break;
    }
    for (std::size_t i = 0; i < k; ++i) {
      const SegmentEnd& e = junction.ends[i];
      trims_[2 * e.segment + (e.at_end ? 1 : 0)] = d[i];
    }
    return clear;
  }

  // How far the junction may trim segment end e: its share of the segment, or (relaxed) what
  // the segment's other end left over.
  [[nodiscard]] double trim_limit(const Junction& junction, const SegmentEnd& e, bool relaxed) const {
    const Polyline& pl = polylines_[e.segment];
    const int other_junction = graph_.junction_of(e.segment, !e.at_end);
    const double other_trim = trims_[2 * e.segment + (e.at_end ? 0 : 1)];
    const bool same_junction = other_junction >= 0 && &graph_.junctions()[static_cast<std::size_t>(other_junction)] == &junction;
    if (relaxed && !same_junction) return std::max(0.0, 0.95 * pl.length - other_trim);
    return (other_junction >= 0 ? 0.47 : 0.85) * pl.length;
  }

  // Whether some other ring j reaches in front of ring i's plane (past the margin).
  [[nodiscard]] bool ring_in_front(const std::vector<Sample>& at, const std::vector<glm::dvec3>& out_normal, std::size_t i) const {
    for (std::size_t j = 0; j < at.size(); ++j) {
      if (i == j) continue;
      const double cos_ij = glm::dot(out_normal[i], at[j].tangent);
      const double reach = glm::dot(out_normal[i], at[j].pos - at[i].pos) +
                           at[j].radius / ratio_ * std::sqrt(std::max(0.0, 1.0 - cos_ij * cos_ij));
      if (!(reach <= -kPlaneMarginRadii * at[i].radius / ratio_)) return true;  // (NaN counts as in front)
    }
    return false;
  }

  // Sizes known up front (junction patches estimated by M faces per incident ring), so the
  // mesh arrays are allocated once instead of growing.
  void reserve_mesh() {
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
      const double angle = 2.0 * kPi * k / m_;
      ring_cos_[static_cast<std::size_t>(k)] = std::cos(angle);
      ring_sin_[static_cast<std::size_t>(k)] = std::sin(angle);
    }
  }

  void place_rings() {
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

  // The arc positions of a segment's rings between the trimmed ends a and b (see RingPlacement).
  void ring_arcs(const Polyline& pl, double a, double b, std::vector<double>& arcs) const {
    arcs.clear();
    if (options_.ring_placement == RingPlacement::kPerPoint) {
      for (double arc : pl.arc) arcs.push_back(a + (arc / pl.length) * (b - a));
      return;
    }
    detail::adaptive_ring_arcs(pl, a, b, arcs);
  }

  // Along the segment, Catmull-Clark converges to the cubic B-spline of the ring sequence, whose
  // value at ring j is (c[j-1] + 4 c[j] + c[j+1]) / 6: bends would cut inward and radius changes
  // flatten. The inner rings' centres and radii are solved for exactly (a tridiagonal system,
  // end rings fixed) so that these averages hit the targets.
  void correct_axial_shrink(std::size_t begin, std::size_t end) {
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

  [[nodiscard]] std::size_t end_ring(const SegmentEnd& e) const {
    return e.at_end ? mesh_.segment_first_ring[e.segment + 1] - 1 : mesh_.segment_first_ring[e.segment];
  }

  // Sets the normals of segment s's rings, starting at the given end with `normal`.
  void propagate_segment(std::uint32_t s, bool from_end, const glm::dvec3& normal) {
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

  void propagate_frames() {
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

  std::uint32_t add_ring_vertices(const glm::dvec3& center, const glm::dvec3& normal, const glm::dvec3& binormal,
                                  double radius) {
    const auto first = static_cast<std::uint32_t>(mesh_.positions_mm.size());
    for (std::size_t m = 0; m < ring_cos_.size(); ++m) {
      mesh_.positions_mm.push_back(center + radius * (ring_cos_[m] * normal + ring_sin_[m] * binormal));
    }
    return first;
  }

  void emit_vertices() {
    mesh_.ring_points = m_;
    for (Ring& ring : mesh_.rings) {
      ring.first_vertex = add_ring_vertices(ring.center_mm, ring.normal, ring.binormal, ring.control_radius_mm);
    }
  }

  void add_face(std::initializer_list<std::uint32_t> vertices, FaceRegion region) {
    mesh_.face_sizes.push_back(static_cast<int>(vertices.size()));
    for (std::uint32_t v : vertices) mesh_.face_vertices.push_back(static_cast<int>(v));
    mesh_.face_regions.push_back(region);
  }

  // Quads between ring a and the next ring b along the tangent (outward, counter-clockwise).
  void add_band(std::uint32_t a, std::uint32_t b, FaceRegion region) {
    const auto m_count = static_cast<std::uint32_t>(m_);
    for (std::uint32_t m = 0; m < m_count; ++m) {
      const std::uint32_t next = (m + 1) % m_count;
      add_face({a + m, a + next, b + next, b + m}, region);
    }
  }

  void emit_tubes() {
    for (std::size_t s = 0; s < model_.segments.size(); ++s) {
      const FaceRegion region{RegionKind::kSegment, model_.segments[s].id};
      for (std::uint32_t r = mesh_.segment_first_ring[s]; r + 1 < mesh_.segment_first_ring[s + 1]; ++r) {
        add_band(mesh_.rings[r].first_vertex, mesh_.rings[r + 1].first_vertex, region);
      }
    }
  }

  void emit_caps() {
    for (const SegmentEnd& e : graph_.free_ends()) {
      const Ring& ring = mesh_.rings[end_ring(e)];
      const glm::dvec3 out = e.at_end ? ring.tangent : -ring.tangent;
      const std::uint32_t extra =
          add_ring_vertices(ring.center_mm + out * (kCapOffsetRadii * ring.control_radius_mm), ring.normal,
                            ring.binormal, kCapRingScale * ring.control_radius_mm);
      const FaceRegion region{RegionKind::kCap, model_.segments[e.segment].id};
      if (e.at_end) add_band(ring.first_vertex, extra, region);
      else add_band(extra, ring.first_vertex, region);
      mesh_.face_sizes.push_back(m_);
      for (int m = 0; m < m_; ++m) {
        const int step = e.at_end ? m : (m_ - m) % m_;
        mesh_.face_vertices.push_back(static_cast<int>(extra) + step);
      }
      mesh_.face_regions.push_back(region);
    }
  }

  std::string emit_junctions() {
    for (std::size_t j = 0; j < graph_.junctions().size(); ++j) {
      const Junction& junction = graph_.junctions()[j];
      std::vector<glm::dvec3> points;
      std::vector<detail::JunctionRing> rings;
      std::vector<detail::JunctionRingFrame> frames;
      std::vector<std::uint32_t> first_vertex;
      for (const SegmentEnd& e : junction.ends) {
        const Ring& ring = mesh_.rings[end_ring(e)];
        rings.push_back({!e.at_end});
        frames.push_back({e.at_end ? -ring.tangent : ring.tangent, ring.normal, ring.binormal, ring.center_mm});
        first_vertex.push_back(ring.first_vertex);
        for (int m = 0; m < m_; ++m) points.push_back(mesh_.positions_mm[ring.first_vertex + static_cast<std::uint32_t>(m)]);
      }
      detail::JunctionPatchResult patch = detail::build_junction_patch(points, rings, m_);
      if (!patch.error.empty() && options_.junction_fallback) {
        std::string what = junction_name(model_, junction, j) + ": " + patch.error;
        patch = detail::build_spherical_junction_patch(points, rings, frames, m_);
        if (patch.error.empty()) mesh_.fallback_junctions.push_back({static_cast<std::uint32_t>(j), std::move(what)});
      }
      if (!patch.error.empty()) return junction_name(model_, junction, j) + ": " + patch.error;
      const FaceRegion region{RegionKind::kJunction, static_cast<std::int32_t>(j)};
      for (const std::vector<int>& face : patch.faces) {
        mesh_.face_sizes.push_back(static_cast<int>(face.size()));
        for (int local : face) {
          mesh_.face_vertices.push_back(static_cast<int>(first_vertex[static_cast<std::size_t>(local / m_)]) +
                                        local % m_);
        }
        mesh_.face_regions.push_back(region);
      }
    }
    return {};
  }

  const VesselModel& model_;
  const VesselGraph& graph_;
  const MeshOptions& options_;
  const int m_;
  double ratio_ = 1.0;
  std::vector<Polyline> polylines_;
  std::vector<double> trims_;
  std::vector<double> ring_cos_, ring_sin_;  // cos / sin(2 pi m / M)
  std::vector<glm::dvec3> target_c_, solved_c_;  // scratch of the axial correction
  std::vector<double> target_r_, solved_r_;
  ControlMesh mesh_;
};

}  // namespace

double tube_shrink_ratio(int ring_points) {
  const double phi = 2.0 * kPi / ring_points;
  // Uniform cubic B-spline through the regular M-gon: at a vertex (P- + 4P + P+)/6, between
  // two vertices (P-1 + 23 P0 + 23 P1 + P2)/48 (radial parts).
  const double at_vertex = (4.0 + 2.0 * std::cos(phi)) / 6.0;
  const double between = (std::cos(1.5 * phi) + 23.0 * std::cos(0.5 * phi)) / 24.0;
  return 0.5 * (at_vertex + between);
}

std::string fallback_summary(const ControlMesh& mesh) {
  const std::size_t n = mesh.fallback_junctions.size();
  if (n == 0) return {};
  std::string out = std::to_string(n) + (n == 1 ? " junction" : " junctions") + " meshed by the spherical-hull fallback: ";
  for (std::size_t i = 0; i < n; ++i) out += (i > 0 ? "; " : "") + mesh.fallback_junctions[i].what;
  return out;
}

ControlMeshResult build_control_mesh(const VesselModel& smoothed, const VesselGraph& graph, const MeshOptions& options) {
  return Builder(smoothed, graph, options).run();
}

}  // namespace cathbox::vessel
