#include "vessel/control_mesh_builder.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

#include <glm/geometric.hpp>

#include "junction_patch.hpp"
#include "vessel/rotation_minimizing_frame.hpp"

namespace cathbox::vessel {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInitialTrimRadii = 1.0;   // first guess of a junction ring's distance, in radii
constexpr double kTrimStepRadii = 0.2;      // step when rings still overlap
constexpr double kPlaneMarginRadii = 0.15;  // how far behind another ring's plane a ring must be
constexpr double kCapOffsetRadii = 0.5;     // cap ring distance beyond the free end
constexpr double kCapRingScale = 0.6;       // cap ring radius / end ring radius
constexpr int kAxialIterations = 4;         // Jacobi steps of the along-the-segment correction

// The smoothed centerline of one segment with arc length and bisected vertex tangents.
struct Polyline {
  std::vector<glm::dvec3> pos;
  std::vector<double> radius;
  std::vector<double> arc;
  std::vector<glm::dvec3> tangent;  // thesis: end points use the end edge, inner points bisect
  std::vector<glm::dvec3> edge_dir;
  double length = 0.0;
};

struct Sample {
  glm::dvec3 pos{0.0};
  glm::dvec3 tangent{0.0, 0.0, 1.0};
  double radius = 0.0;
};

[[nodiscard]] Polyline make_polyline(const Segment& s) {
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

[[nodiscard]] Sample sample(const Polyline& pl, double t) {
  t = std::clamp(t, 0.0, pl.length);
  const auto it = std::upper_bound(pl.arc.begin(), pl.arc.end(), t);
  std::size_t j = it == pl.arc.begin() ? 0 : static_cast<std::size_t>(it - pl.arc.begin()) - 1;
  j = std::min(j, pl.arc.size() - 2);
  const double span = pl.arc[j + 1] - pl.arc[j];
  const double a = span > 0.0 ? std::clamp((t - pl.arc[j]) / span, 0.0, 1.0) : 0.0;
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
    ControlMeshResult result;
    if (m_ < 3 || m_ > 256) {
      result.error = "ring size must be between 3 and 256, got " + std::to_string(m_);
      return result;
    }
    if (options_.smoothing_passes < 0) {
      result.error = "smoothing passes must be >= 0";
      return result;
    }
    ratio_ = options_.compensate_shrink ? tube_shrink_ratio(m_) : 1.0;
    for (const Segment& s : model_.segments) {
      polylines_.push_back(make_polyline(s));
      if (s.points.size() < 2 || !(polylines_.back().length > 0.0)) {
        result.error = "segment " + std::to_string(s.id) + " has zero length";
        return result;
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
    result.error = emit_junctions();
    result.mesh = std::move(mesh_);
    return result;
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
      const SegmentEnd& e = junction.ends[i];
      const Polyline& pl = polylines_[e.segment];
      const double r = sample(pl, end_arc(e, 0.0)).radius / ratio_;
      const int other_junction = graph_.junction_of(e.segment, !e.at_end);
      const double other_trim = trims_[2 * e.segment + (e.at_end ? 0 : 1)];
      const bool same_junction = other_junction >= 0 && &graph_.junctions()[static_cast<std::size_t>(other_junction)] == &junction;
      if (relaxed && !same_junction) max_d[i] = std::max(0.0, 0.95 * pl.length - other_trim);
      else max_d[i] = (other_junction >= 0 ? 0.47 : 0.85) * pl.length;
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
        for (std::size_t j = 0; j < k; ++j) {
          if (i == j) continue;
          const double cos_ij = glm::dot(out_normal[i], at[j].tangent);
          const double reach = glm::dot(out_normal[i], at[j].pos - at[i].pos) +
                               at[j].radius / ratio_ * std::sqrt(std::max(0.0, 1.0 - cos_ij * cos_ij));
          if (reach <= -kPlaneMarginRadii * at[i].radius / ratio_) continue;
          // Ring j reaches in front of ring i's plane: move ring i further out.
          clear = false;
          if (d[i] < max_d[i]) {
            d[i] = std::min(max_d[i], d[i] + kTrimStepRadii * at[i].radius / ratio_);
            changed = true;
          }
          break;
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
    for (std::size_t s = 0; s < model_.segments.size(); ++s) {
      const Polyline& pl = polylines_[s];
      mesh_.segment_first_ring.push_back(static_cast<std::uint32_t>(mesh_.rings.size()));
      const double a = trims_[2 * s];
      const double b = pl.length - trims_[2 * s + 1];
      for (double arc : pl.arc) {
        const double t = a + (arc / pl.length) * (b - a);
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

  // Along the segment, Catmull-Clark converges to the cubic B-spline of the ring sequence, whose
  // value at ring j is (c[j-1] + 4 c[j] + c[j+1]) / 6: bends would cut inward and radius peaks
  // flatten. A few Jacobi steps move the inner rings' centres and radii so that these averages
  // hit the targets (the end rings stay where they are).
  void correct_axial_shrink(std::size_t begin, std::size_t end) {
    if (end - begin < 3) return;
    std::vector<glm::dvec3> target_c;
    std::vector<double> target_r;
    for (std::size_t j = begin; j < end; ++j) {
      target_c.push_back(mesh_.rings[j].center_mm);
      target_r.push_back(mesh_.rings[j].control_radius_mm);
    }
    std::vector<glm::dvec3> c = target_c;
    std::vector<double> r = target_r;
    const std::size_t n = c.size();
    for (int iteration = 0; iteration < kAxialIterations; ++iteration) {
      std::vector<glm::dvec3> next_c = c;
      std::vector<double> next_r = r;
      for (std::size_t j = 1; j + 1 < n; ++j) {
        next_c[j] = c[j] + target_c[j] - (c[j - 1] + 4.0 * c[j] + c[j + 1]) / 6.0;
        next_r[j] = std::max(0.5 * target_r[j], r[j] + target_r[j] - (r[j - 1] + 4.0 * r[j] + r[j + 1]) / 6.0);
      }
      c.swap(next_c);
      r.swap(next_r);
    }
    for (std::size_t j = 1; j + 1 < n; ++j) {
      // In a bend each ring point is pulled towards the centre of curvature by its own distance
      // from it times alpha^2 / 6 (alpha: turning angle per ring); moving the centre makes up for
      // the centre's share only, so the radius gets the rest.
      const double cos_2a = std::clamp(glm::dot(mesh_.rings[begin + j - 1].tangent, mesh_.rings[begin + j + 1].tangent), -1.0, 1.0);
      const double alpha = 0.5 * std::acos(cos_2a);
      mesh_.rings[begin + j].center_mm = c[j];
      mesh_.rings[begin + j].control_radius_mm = r[j] * (1.0 + alpha * alpha / 6.0);
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
      std::vector<std::uint32_t> first_vertex;
      for (const SegmentEnd& e : junction.ends) {
        const Ring& ring = mesh_.rings[end_ring(e)];
        rings.push_back({!e.at_end});
        first_vertex.push_back(ring.first_vertex);
        for (int m = 0; m < m_; ++m) points.push_back(mesh_.positions_mm[ring.first_vertex + static_cast<std::uint32_t>(m)]);
      }
      const detail::JunctionPatchResult patch = detail::build_junction_patch(points, rings, m_);
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

ControlMeshResult build_control_mesh(const VesselModel& smoothed, const VesselGraph& graph, const MeshOptions& options) {
  return Builder(smoothed, graph, options).run();
}

}  // namespace cathbox::vessel
