#include "junction_fit.hpp"

#include <algorithm>
#include <span>
#include <cmath>
#include <limits>
#include <array>
#include <optional>
#include <unordered_map>

#include <glm/geometric.hpp>

#include "centerline_polyline.hpp"
#include "junction_fit_move.hpp"
#include "vessel/control_mesh_builder.hpp"

namespace cathbox::vessel::detail {
namespace {

constexpr double kAxisReachRadii = 2.0;  // a branch's axis is kept this far beyond its ring
constexpr double kAxisStepRadii = 0.5;   // axis sample spacing, in radii

// The constructor's steps.

// The part of one branch's axis near the junction, sampled from the junction end out to
// kAxisReachRadii beyond its ring; nullopt when the branch's centreline is degenerate.
[[nodiscard]] std::optional<JunctionFit::Axis> branch_axis(const Segment& segment, const SegmentEnd& e, const ControlMesh& control) {
  const Polyline pl = make_polyline(segment);
  if (pl.pos.size() < 2 || !(pl.length > 0.0)) return std::nullopt;
  const std::uint32_t first_ring = control.segment_first_ring[e.segment];
  const std::uint32_t last_ring = control.segment_first_ring[e.segment + 1] - 1;
  const Ring& ring = control.rings[e.at_end ? last_ring : first_ring];
  JunctionFit::Axis axis;
  axis.trim = e.at_end ? pl.length - ring.arc_mm : ring.arc_mm;
  axis.ring_radius = ring.radius_mm;
  const double reach = std::min(pl.length, axis.trim + kAxisReachRadii * ring.radius_mm);
  const int steps = std::clamp(static_cast<int>(std::ceil(reach / (kAxisStepRadii * ring.radius_mm))), 1, 256);
  axis.step = reach / steps;
  glm::dvec3 lo(std::numeric_limits<double>::infinity());
  glm::dvec3 hi(-std::numeric_limits<double>::infinity());
  for (int k = 0; k <= steps; ++k) {
    const double from_end = axis.step * k;
    const Sample s = sample(pl, e.at_end ? pl.length - from_end : from_end);
    axis.pos.push_back(s.pos);
    axis.radius.push_back(s.radius);
    lo = glm::min(lo, s.pos);
    hi = glm::max(hi, s.pos);
    axis.max_radius = std::max(axis.max_radius, s.radius);
  }
  axis.bound_center = 0.5 * (lo + hi);
  axis.bound_radius = 0.5 * glm::length(hi - lo);
  return axis;
}

// The first tube face of every segment: tube faces come first in the control mesh, segment by
// segment, M per band.
[[nodiscard]] std::vector<std::uint32_t> first_tube_faces(const ControlMesh& control) {
  std::vector<std::uint32_t> first_tube_face;
  std::uint32_t face = 0;
  for (std::size_t s = 0; s + 1 < control.segment_first_ring.size(); ++s) {
    first_tube_face.push_back(face);
    face += static_cast<std::uint32_t>(control.ring_points) * (control.segment_first_ring[s + 1] - control.segment_first_ring[s] - 1);
  }
  return first_tube_face;
}

// The tube faces of branch end `e` within kFitTubeFadeRadii beyond its ring (those that follow
// the fit), into axis.fade_faces.
void collect_fade_faces(const ControlMesh& control, const SegmentEnd& e, const std::vector<std::uint32_t>& first_tube_face,
                        JunctionFit::Axis& axis) {
  const std::uint32_t first_ring = control.segment_first_ring[e.segment];
  const std::uint32_t bands = control.segment_first_ring[e.segment + 1] - first_ring - 1;
  const double ring_arc = control.rings[e.at_end ? first_ring + bands : first_ring].arc_mm;
  for (std::uint32_t k = 0; k < bands; ++k) {
    const std::uint32_t band = e.at_end ? bands - 1 - k : k;
    const std::uint32_t near_ring = e.at_end ? first_ring + band + 1 : first_ring + band;
    if (std::abs(control.rings[near_ring].arc_mm - ring_arc) >= kFitTubeFadeRadii * axis.ring_radius) break;
    for (int m = 0; m < control.ring_points; ++m) {
      axis.fade_faces.push_back(first_tube_face[e.segment] + band * static_cast<std::uint32_t>(control.ring_points) +
                                static_cast<std::uint32_t>(m));
    }
  }
}

}  // namespace

JunctionFit::JunctionFit(const VesselModel& smoothed, const VesselGraph& graph, const ControlMesh& control)
    : control_(control) {
  std::vector<std::uint32_t> first_tube_face;  // per segment index, filled on first use
  std::vector<int> slot(graph.junctions().size(), -1);  // junction -> its entry in junctions_
  for (std::size_t j = 0; j < graph.junctions().size(); ++j) {
    const Junction& junction = graph.junctions()[j];
    bool long_patch = false;
    FittedJunction fitted;
    for (const SegmentEnd& e : junction.ends) {
      std::optional<Axis> axis = branch_axis(smoothed.segments[e.segment], e, control);
      if (!axis) return;
      long_patch = long_patch || axis->trim > kFitTrimRadii * axis->ring_radius;
      fitted.axes.push_back(std::move(*axis));
    }
    if (!long_patch) continue;
    if (first_tube_face.empty()) first_tube_face = first_tube_faces(control);
    for (std::size_t b = 0; b < junction.ends.size(); ++b) collect_fade_faces(control, junction.ends[b], first_tube_face, fitted.axes[b]);
    slot[j] = static_cast<int>(junctions_.size());
    junctions_.push_back(std::move(fitted));
  }
  if (junctions_.empty()) return;
  for (std::size_t f = 0; f < control.face_regions.size(); ++f) {
    const FaceRegion region = control.face_regions[f];
    if (region.kind != RegionKind::kJunction || region.id < 0 || static_cast<std::size_t>(region.id) >= slot.size()) continue;
    const int s = slot[static_cast<std::size_t>(region.id)];
    if (s >= 0) junctions_[static_cast<std::size_t>(s)].patch_faces.push_back(static_cast<std::uint32_t>(f));
  }
}

namespace {

// A vertex of the marked faces (local numbering): its junction and branch (-1: the patch,
// preferred; b: the tube of branch b beyond its ring) and how many marked faces hold it.
struct PatchVertex {
  int vertex;
  int junction;
  int branch;
  int faces = 0;
};

// The marked faces of one refinement level: their vertices, every face corner as (vertex, next,
// diagonal, previous) in local numbers, and the Catmull-Clark limit stencils built from them.
class MarkedPatch {
 public:
  explicit MarkedPatch(const RefinedLevel& level)
      : level_(level), local_of_(static_cast<std::size_t>(level.vertex_count()), -1) {}

  // Marks the level's descendants of the control faces `faces` (first_child: the first face of
  // every control face's descendants). False when one of them is no quad.
  [[nodiscard]] bool mark(const std::vector<std::uint32_t>& first_child, const std::vector<std::uint32_t>& faces,
                          int junction, int branch) {
    for (std::uint32_t f : faces) {
      for (std::uint32_t child = first_child[f]; child < first_child[f + 1]; ++child) {
        const std::span<const int> q = level_.face_vertices(static_cast<int>(child));
        if (q.size() != 4) return false;
        mark_quad(q, junction, branch);
      }
    }
    return true;
  }

  // Corners grouped by vertex (counting sort) and the positions, gathered once.
  void gather() {
    first_corner.assign(locals.size() + 1, 0);
    for (const PatchVertex& l : locals) first_corner[&l - locals.data() + 1] = static_cast<std::size_t>(l.faces);
    for (std::size_t i = 0; i < locals.size(); ++i) first_corner[i + 1] += first_corner[i];
    around.resize(corners.size());
    {
      std::vector<std::size_t> fill(first_corner.begin(), first_corner.end() - 1);
      for (const auto& c : corners) around[fill[static_cast<std::size_t>(c[0])]++] = {c[1], c[2], c[3]};
    }
    pos.resize(locals.size());
    for (std::size_t i = 0; i < locals.size(); ++i) pos[i] = glm::dvec3(level_.point(locals[i].vertex));
  }

  // Catmull-Clark limit of an interior quad-mesh vertex of valence n:
  // (n^2 v + 4 sum(edge neighbours) + sum(diagonals)) / (n (n + 5)); each edge neighbour is in two
  // of the vertex's faces, so 4 sum(e) = 2 sum over faces of (next + previous).
  [[nodiscard]] glm::dvec3 limit_of(std::size_t i) const {
    glm::dvec3 sum(0.0);
    for (std::size_t c = first_corner[i]; c < first_corner[i + 1]; ++c) {
      const auto& a = around[c];
      sum += 2.0 * (pos[static_cast<std::size_t>(a[0])] + pos[static_cast<std::size_t>(a[2])]) + pos[static_cast<std::size_t>(a[1])];
    }
    const double n = static_cast<double>(first_corner[i + 1] - first_corner[i]);
    return (n * n * pos[i] + sum) / (n * (n + 5.0));
  }

  // Every marked face's four corners are all its vertex's faces, and it is not on a boundary:
  // its limit stencil is known.
  [[nodiscard]] bool interior(std::size_t i) const {
    const PatchVertex& l = locals[i];
    return l.faces == level_.vertex_face_count(l.vertex) && !level_.boundary_vertex(l.vertex);
  }

  std::vector<PatchVertex> locals;
  std::vector<std::array<int, 4>> corners;
  std::vector<std::size_t> first_corner;
  std::vector<std::array<int, 3>> around;  // (next, diagonal, previous) per corner
  std::vector<glm::dvec3> pos;

 private:
  void mark_quad(std::span<const int> q, int junction, int branch) {
    std::array<int, 4> l{};
    for (std::size_t i = 0; i < 4; ++i) {
      int& slot = local_of_[static_cast<std::size_t>(q[i])];
      if (slot < 0) {
        slot = static_cast<int>(locals.size());
        locals.push_back({q[i], junction, branch});
      } else if (branch < 0) {
        locals[static_cast<std::size_t>(slot)].junction = junction;
        locals[static_cast<std::size_t>(slot)].branch = branch;
      }
      l[i] = slot;
    }
    for (std::size_t i = 0; i < 4; ++i) {
      corners.push_back({l[i], l[(i + 1) & 3], l[(i + 2) & 3], l[(i + 3) & 3]});
      ++locals[static_cast<std::size_t>(l[i])].faces;
    }
  }

  const RefinedLevel& level_;
  std::vector<int> local_of_;
};

// Moves the vertices until their limit positions reach start + displacement (Richardson
// iteration v += target - limit(v), all at once per step; the limit stencil is a smoothing,
// so smooth differences settle in a few steps). Only vertices with a displacement move; the
// others keep their positions.
void reach_targets(MarkedPatch& patch, const std::vector<std::size_t>& interior,
                   const std::vector<glm::dvec3>& start_limit, const std::vector<glm::dvec3>& displacement) {
  std::vector<std::size_t> moving;
  for (std::size_t q = 0; q < interior.size(); ++q) {
    if (glm::dot(displacement[q], displacement[q]) > 0.0) moving.push_back(q);
  }
  std::vector<glm::dvec3> step(moving.size());
  for (int iteration = 0; iteration < kFitIterations; ++iteration) {
    for (std::size_t m = 0; m < moving.size(); ++m) {
      const std::size_t q = moving[m];
      step[m] = start_limit[q] + displacement[q] - patch.limit_of(interior[q]);
    }
    for (std::size_t m = 0; m < moving.size(); ++m) patch.pos[interior[moving[m]]] += step[m];
  }
}

// Where a vertex's neighbours stay (the weight falls off next to it) its limit can only follow
// by the vertex moving ~2.25 times as far, which may fold the faces around it: a marked face that
// turned by more than kFitMaxTurn_deg has its vertices' moves halved, up to kFitUnfoldSteps times.
void unfold(MarkedPatch& patch, const RefinedLevel& level) {
  const double cos_max_turn = std::cos(kFitMaxTurn_deg * 3.14159265358979323846 / 180.0);
  const auto quad_normal = [](const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    return glm::cross(c - a, d - b);
  };
  std::vector<glm::dvec3> before(patch.locals.size());
  for (std::size_t i = 0; i < patch.locals.size(); ++i) before[i] = glm::dvec3(level.point(patch.locals[i].vertex));
  std::vector<char> halve(patch.locals.size(), 0);
  for (int step = 0; step < kFitUnfoldSteps; ++step) {
    bool any_turned = false;
    for (std::size_t c = 0; c < patch.corners.size(); c += 4) {  // each face's four corners, in order
      const auto& f = patch.corners[c];
      const auto at = [&](const std::vector<glm::dvec3>& p, std::size_t corner) { return p[static_cast<std::size_t>(f[corner])]; };
      const glm::dvec3 n0 = quad_normal(at(before, 0), at(before, 1), at(before, 2), at(before, 3));
      const glm::dvec3 n1 = quad_normal(at(patch.pos, 0), at(patch.pos, 1), at(patch.pos, 2), at(patch.pos, 3));
      if (glm::dot(n0, n1) >= cos_max_turn * glm::length(n0) * glm::length(n1)) continue;
      any_turned = true;
      for (int v : f) halve[static_cast<std::size_t>(v)] = 1;
    }
    if (!any_turned) break;
    for (std::size_t i = 0; i < patch.locals.size(); ++i) {
      if (halve[i]) patch.pos[i] = 0.5 * (patch.pos[i] + before[i]);
      halve[i] = 0;
    }
  }
}

}  // namespace

void JunctionFit::apply(RefinedLevel& level) {
  const int k = level.level();
  if (k == 0) return;  // the control mesh: the patch has no vertices of its own to move
  // The first face of every control face's descendants at this level.
  std::vector<std::uint32_t> first_child(control_.face_sizes.size() + 1, 0);
  for (std::size_t f = 0; f < control_.face_sizes.size(); ++f) {
    first_child[f + 1] = first_child[f] + (static_cast<std::uint32_t>(control_.face_sizes[f]) << (2 * (k - 1)));
  }
  if (first_child.back() != static_cast<std::uint32_t>(level.face_count())) return;  // not uniform refinement

  // The vertices of the tubes' fading faces, then of the patch (which takes the vertices the two share).
  MarkedPatch patch(level);
  for (std::size_t j = 0; j < junctions_.size(); ++j) {
    for (std::size_t b = 0; b < junctions_[j].axes.size(); ++b) {
      if (!patch.mark(first_child, junctions_[j].axes[b].fade_faces, static_cast<int>(j), static_cast<int>(b))) return;
    }
    if (!patch.mark(first_child, junctions_[j].patch_faces, static_cast<int>(j), -1)) return;
  }
  patch.gather();

  // Every vertex whose faces are all marked (so its limit stencil is known) gets a displacement
  // of its limit position: onto the nearest tube, by the weight (0 where it does not apply).
  std::vector<std::size_t> interior;
  std::vector<glm::dvec3> start_limit, displacement;
  TubeSearch search;
  std::vector<char> touched(junctions_.size(), 0);
  for (std::size_t i = 0; i < patch.locals.size(); ++i) {
    if (!patch.interior(i)) continue;
    const PatchVertex& l = patch.locals[i];
    interior.push_back(i);
    const glm::dvec3 at = patch.limit_of(i);
    start_limit.push_back(at);
    displacement.emplace_back(0.0);
    const std::optional<FitMove> fit = fit_move(junctions_[static_cast<std::size_t>(l.junction)].axes, l.branch, at, search);
    if (!fit) continue;
    displacement.back() = fit->move_mm * fit->direction;
    report_.max_move_mm = std::max(report_.max_move_mm, std::abs(fit->move_mm));
    touched[static_cast<std::size_t>(l.junction)] = 1;
  }
  reach_targets(patch, interior, start_limit, displacement);
  unfold(patch, level);
  std::size_t moved = 0;
  for (std::size_t q = 0; q < interior.size(); ++q) {
    if (glm::dot(displacement[q], displacement[q]) == 0.0) continue;
    level.set_point(patch.locals[interior[q]].vertex, glm::vec3(patch.pos[interior[q]]));
    ++moved;
  }
  report_.vertices = moved;
  report_.junctions = static_cast<std::size_t>(std::count(touched.begin(), touched.end(), 1));
}

}  // namespace cathbox::vessel::detail
