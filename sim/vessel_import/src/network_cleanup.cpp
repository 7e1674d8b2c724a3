#include "network_cleanup.hpp"

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

namespace cathbox::vessel_import::detail {

namespace {

// Consecutive points closer than a millionth of their radius are one point.
void drop_repeated_points(Edge& e) {
  std::vector<CenterlinePoint> kept;
  for (std::size_t i = 0; i < e.points.size(); ++i) {
    const CenterlinePoint& p = e.points[i];
    if (!kept.empty() && glm::length(p.pos_mm - kept.back().pos_mm) <= 1e-6 * std::max(p.radius_mm, 1e-3)) {
      if (i + 1 == e.points.size()) kept.back() = p;  // keep the node's own point at the end
      continue;
    }
    kept.push_back(p);
  }
  e.points = std::move(kept);
}

}  // namespace

// Branches that collapsed to a point merge their two nodes.
void merge_collapsed(Graph& g) {
  for (Edge& e : g.edges()) {
    if (e.alive) drop_repeated_points(e);
  }
  for (std::size_t e = 0; e < g.edges().size(); ++e) {
    Edge& edge = g.edges()[e];
    if (!edge.alive || edge.points.size() >= 2) continue;
    edge.alive = false;
    if (edge.a != edge.b) {
      const std::size_t from = edge.b;
      const std::size_t to = edge.a;
      for (Edge& other : g.edges()) {
        if (!other.alive) continue;
        if (other.a == from) other.a = to;
        if (other.b == from) other.b = to;
      }
    }
  }
}

namespace {

// True when edge e between two junctions is shorter than kContractRadii of their radius, and no
// other branch joins the same two nodes (contracting it would make that one a loop on one node).
[[nodiscard]] bool contractible(const Graph& g, const std::vector<std::vector<std::size_t>>& incident, std::size_t e) {
  const Edge& edge = g.edges()[e];
  if (!edge.alive || edge.a == edge.b) return false;
  if (incident[edge.a].size() < 3 || incident[edge.b].size() < 3) return false;
  const double r = std::max(node_radius(g, incident[edge.a], edge.a), node_radius(g, incident[edge.b], edge.b));
  if (length_of(edge.points) >= kContractRadii * r) return false;
  bool parallel = false;
  for (std::size_t other : incident[edge.a]) {
    const Edge& o = g.edges()[other];
    parallel = parallel || (other != e && ((o.a == edge.a && o.b == edge.b) || (o.a == edge.b && o.b == edge.a)));
  }
  return !parallel;
}

}  // namespace

// Short branches between two junctions: contracted into one junction at their middle.
void contract_short_branches(Graph& g, NetworkStats& stats) {
  for (bool changed = true; changed;) {
    changed = false;
    const auto incident = g.incidence();
    for (std::size_t e = 0; e < g.edges().size() && !changed; ++e) {
      if (!contractible(g, incident, e)) continue;
      const Edge& edge = g.edges()[e];
      const std::size_t keep = edge.a;
      const std::size_t gone = edge.b;
      const glm::dvec3 middle = 0.5 * (g.node(keep) + g.node(gone));
      g.edges()[e].alive = false;
      for (Edge& other : g.edges()) {
        if (!other.alive) continue;
        if (other.a == gone) other.a = keep;
        if (other.b == gone) other.b = keep;
      }
      g.move_node(keep, middle);
      ++stats.contracted;
      changed = true;
    }
  }
}

// Free-ended branches shorter than kStubRadii of their junction's radius: pruned (the tip lies
// inside the vessels there). The junction keeps at least two other branches.
void prune_stubs(Graph& g, NetworkStats& stats) {
  for (bool changed = true; changed;) {
    changed = false;
    const auto incident = g.incidence();
    for (std::size_t e = 0; e < g.edges().size() && !changed; ++e) {
      const Edge& edge = g.edges()[e];
      if (!edge.alive || edge.a == edge.b) continue;
      const bool free_a = incident[edge.a].size() == 1;
      const bool free_b = incident[edge.b].size() == 1;
      if (free_a == free_b) continue;
      const std::size_t junction = free_a ? edge.b : edge.a;
      if (incident[junction].size() < 3) continue;
      const double length = length_of(edge.points);
      if (length >= kStubRadii * node_radius(g, incident[junction], junction)) continue;
      g.edges()[e].alive = false;
      ++stats.stubs;
      stats.longest_stub_mm = std::max(stats.longest_stub_mm, length);
      changed = true;
    }
  }
}

// A branch from a node back to itself: split in two at its middle point.
void split_self_loops(Graph& g) {
  for (std::size_t e = 0; e < g.edges().size(); ++e) {
    Edge& edge = g.edges()[e];
    if (!edge.alive || edge.a != edge.b) continue;
    if (edge.points.size() < 3) {
      edge.alive = false;
      continue;
    }
    const std::size_t mid = edge.points.size() / 2;
    const std::size_t node = g.add_node(edge.points[mid].pos_mm);
    std::vector<CenterlinePoint> second(edge.points.begin() + static_cast<std::ptrdiff_t>(mid), edge.points.end());
    edge.points.resize(mid + 1);
    const std::size_t end = edge.b;
    edge.b = node;
    const std::string name = edge.name;
    g.add_edge(std::move(second), node, end, name);
  }
}

namespace {

// Joins the two branches at node n (exactly two ends there, of two different branches) into one;
// false when n stays (an end of both is n itself, or joining would close a branch on itself).
bool join_at(Graph& g, const std::vector<std::size_t>& at_node, std::size_t n) {
  const std::size_t e1 = at_node[0];
  const std::size_t e2 = at_node[1];
  Edge first = g.edges()[e1];
  Edge second = g.edges()[e2];
  if (first.b != n) {
    std::reverse(first.points.begin(), first.points.end());
    std::swap(first.a, first.b);
  }
  if (second.a != n) {
    std::reverse(second.points.begin(), second.points.end());
    std::swap(second.a, second.b);
  }
  if (first.a == n || second.b == n) return false;
  if (first.a == second.b) return false;  // joining would close a branch on itself: keep this node
  first.points.insert(first.points.end(), second.points.begin() + 1, second.points.end());
  first.b = second.b;
  if (first.name.empty()) first.name = second.name;
  g.edges()[e1] = std::move(first);
  g.edges()[e2].alive = false;
  return true;
}

}  // namespace

// Chains through nodes with exactly two branch ends (of two different branches): one segment.
// Then branches left without length are dropped.
void join_chains(Graph& g, NetworkStats& stats) {
  for (bool changed = true; changed;) {
    changed = false;
    const auto incident = g.incidence();
    for (std::size_t n = 0; n < incident.size() && !changed; ++n) {
      if (incident[n].size() != 2 || incident[n][0] == incident[n][1]) continue;
      if (!join_at(g, incident[n], n)) continue;
      ++stats.joined;
      changed = true;
    }
  }
  for (Edge& e : g.edges()) {
    if (e.alive && (e.points.size() < 2 || !(length_of(e.points) > 0.0))) e.alive = false;
  }
}

namespace {

// The radius of the network at a location (interpolated along its piece).
[[nodiscard]] double radius_at(const Graph& g, const Location& at) {
  const Edge& edge = g.edges()[at.edge];
  return edge.points[at.piece].radius_mm + at.t * (edge.points[at.piece + 1].radius_mm - edge.points[at.piece].radius_mm);
}

// Where a free end's own axis, extended past it by up to kReachRadii of its radius, enters another
// polyline's lumen (the first sample, every quarter radius, within that polyline's radius of it):
// a branch stopping at its parent's wall has its centre the parent's radius plus its own from
// the parent's axis, so this joins it up to one more own radius short of that. Two vessels side
// by side never enter each other's lumen along their own axes.
[[nodiscard]] Location reach_along_axis(const Graph& g, const Edge& edge, bool at_front,
                                        const std::vector<std::size_t>& skip) {
  const std::vector<CenterlinePoint>& p = edge.points;
  const std::size_t back = std::min<std::size_t>(3, p.size() - 1);  // the end's direction over 3 pieces
  const CenterlinePoint& end = at_front ? p.front() : p.back();
  const glm::dvec3 from = at_front ? p[back].pos_mm : p[p.size() - 1 - back].pos_mm;
  const double length = glm::length(end.pos_mm - from);
  if (length <= 0.0 || end.radius_mm <= 0.0) return {};
  const glm::dvec3 dir = (end.pos_mm - from) / length;
  const double step = 0.25 * end.radius_mm;
  for (double s = step; s <= kReachRadii * end.radius_mm + 1e-9; s += step) {
    const Location at = g.nearest(end.pos_mm + s * dir, skip);
    if (at.edge != kNone && at.distance <= radius_at(g, at)) return at;
  }
  return {};
}

}  // namespace

// Free ends within kJoinRadii of another polyline are bridged to their nearest point there, and
// ends whose extended axis enters another polyline's lumen (reach_along_axis) to the place it
// enters (splitting it, or joining its end node within kSnapRadii). The polylines sharing the
// end's own piece of network (its edge and the edges at its other node) are not candidates: a
// short branch lies near its parent without being meant to join it twice.
void join_near_ends(Graph& g, NetworkStats& stats) {
  for (std::size_t n = 0; n < g.node_count(); ++n) {
    const std::vector<std::vector<std::size_t>> incident = g.incidence();
    if (incident[n].size() != 1) continue;
    const std::size_t e = incident[n].front();
    const Edge& edge = g.edges()[e];
    const std::size_t other = edge.a == n ? edge.b : edge.a;
    std::vector<std::size_t> skip = incident[other];
    skip.push_back(e);
    std::sort(skip.begin(), skip.end());
    const CenterlinePoint end = edge.a == n ? edge.points.front() : edge.points.back();
    Location at = g.nearest(end.pos_mm, skip);
    if (at.edge == kNone || at.distance > kJoinRadii * std::max(end.radius_mm, radius_at(g, at))) {
      at = reach_along_axis(g, edge, edge.a == n, skip);
      if (at.edge == kNone) continue;
    }
    const std::size_t m = g.attach(at, end.radius_mm);  // may add an edge: `edge` is not used after
    if (m == n || m == other) continue;
    g.bridge(e, n, m);
    ++stats.ends_joined;
    stats.widest_join_gap_mm = std::max(stats.widest_join_gap_mm, glm::length(g.node(m) - end.pos_mm));
  }
}

}  // namespace cathbox::vessel_import::detail
