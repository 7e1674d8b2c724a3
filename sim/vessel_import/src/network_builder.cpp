#include "vessel_import/network_builder.hpp"

#include "network_orient.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <unordered_map>

#include <glm/geometric.hpp>

namespace cathbox::vessel_import {
namespace {

using vessel::CenterlinePoint;

constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

struct Edge {
  std::vector<CenterlinePoint> points;  // first and last at their nodes' positions
  std::size_t a = 0;                    // node at points.front()
  std::size_t b = 0;                    // node at points.back()
  std::string name;
  bool alive = true;
};

// Where a point is nearest to the network: edge, piece k (points k, k + 1), fraction t.
struct Location {
  std::size_t edge = kNone;
  std::size_t piece = 0;
  double t = 0.0;
  double distance = std::numeric_limits<double>::infinity();
};

class Graph {
 public:
  std::size_t add_node(const glm::dvec3& p) {
    nodes_.push_back(p);
    return nodes_.size() - 1;
  }
  std::size_t add_edge(std::vector<CenterlinePoint> points, std::size_t a, std::size_t b, std::string name) {
    points.front().pos_mm = nodes_[a];
    points.back().pos_mm = nodes_[b];
    edges_.push_back({std::move(points), a, b, std::move(name), true});
    return edges_.size() - 1;
  }
  [[nodiscard]] const glm::dvec3& node(std::size_t n) const { return nodes_[n]; }
  [[nodiscard]] std::size_t node_count() const { return nodes_.size(); }
  std::vector<Edge>& edges() { return edges_; }
  [[nodiscard]] const std::vector<Edge>& edges() const { return edges_; }

  // The nearest place on the network; `skip` edges (sorted) are left out.
  [[nodiscard]] Location nearest(const glm::dvec3& p, const std::vector<std::size_t>& skip = {}) const {
    Location best;
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      const Edge& edge = edges_[e];
      if (!edge.alive || std::binary_search(skip.begin(), skip.end(), e)) continue;
      for (std::size_t k = 0; k + 1 < edge.points.size(); ++k) {
        const glm::dvec3 a = edge.points[k].pos_mm;
        const glm::dvec3 d = edge.points[k + 1].pos_mm - a;
        const double len2 = glm::dot(d, d);
        const double t = len2 > 0.0 ? std::clamp(glm::dot(p - a, d) / len2, 0.0, 1.0) : 0.0;
        const double dist = glm::length(p - (a + t * d));
        if (dist < best.distance) best = {e, k, t, dist};
      }
    }
    return best;
  }

  // The node at `at` (an existing end node when within kSnapRadii of it along the edge, else a
  // new node splitting the edge there).
  std::size_t attach(const Location& at, double radius_mm) {
    Edge& edge = edges_[at.edge];
    double arc = 0.0;
    double length = 0.0;
    for (std::size_t k = 0; k + 1 < edge.points.size(); ++k) {
      const double len = glm::length(edge.points[k + 1].pos_mm - edge.points[k].pos_mm);
      if (k < at.piece) arc += len;
      if (k == at.piece) arc += at.t * len;
      length += len;
    }
    const double to_b = length - arc;
    if (std::min(arc, to_b) <= kSnapRadii * radius_mm) return arc <= to_b ? edge.a : edge.b;
    // Split: the new node at the location, radius interpolated.
    const CenterlinePoint& p0 = edge.points[at.piece];
    const CenterlinePoint& p1 = edge.points[at.piece + 1];
    CenterlinePoint mid;
    mid.pos_mm = p0.pos_mm + at.t * (p1.pos_mm - p0.pos_mm);
    mid.radius_mm = p0.radius_mm + at.t * (p1.radius_mm - p0.radius_mm);
    const std::size_t node = add_node(mid.pos_mm);
    std::vector<CenterlinePoint> first(edge.points.begin(), edge.points.begin() + static_cast<std::ptrdiff_t>(at.piece + 1));
    std::vector<CenterlinePoint> second(edge.points.begin() + static_cast<std::ptrdiff_t>(at.piece + 1), edge.points.end());
    if (glm::length(first.back().pos_mm - mid.pos_mm) > 0.0) first.push_back(mid);
    if (glm::length(second.front().pos_mm - mid.pos_mm) > 0.0) second.insert(second.begin(), mid);
    if (first.size() < 2) first.insert(first.begin(), edge.points.front());
    if (second.size() < 2) second.push_back(edge.points.back());
    // At the new junction each half keeps its own radius (its sample next to the junction): the
    // sample there may be where one tract ended and the next began, with the former's radius.
    first.back().radius_mm = first[first.size() - 2].radius_mm;
    second.front().radius_mm = second[1].radius_mm;
    const std::size_t b = edge.b;
    const std::string name = edge.name;
    edge.points = std::move(first);
    edge.b = node;
    edge.points.back().pos_mm = nodes_[node];
    add_edge(std::move(second), node, b, name);  // may reallocate edges_: `edge` is not used after
    return node;
  }

  // Incident edge ends per node (an edge with both ends at a node appears twice).
  [[nodiscard]] std::vector<std::vector<std::size_t>> incidence() const {
    std::vector<std::vector<std::size_t>> out(nodes_.size());
    for (std::size_t e = 0; e < edges_.size(); ++e) {
      if (!edges_[e].alive) continue;
      out[edges_[e].a].push_back(e);
      out[edges_[e].b].push_back(e);
    }
    return out;
  }

  // Edge e's end at node n continues to node m: a bridge point at m, with the end's radius.
  void bridge(std::size_t e, std::size_t n, std::size_t m) {
    Edge& edge = edges_[e];
    if (edge.a == n) {
      edge.points.insert(edge.points.begin(), CenterlinePoint{nodes_[m], edge.points.front().radius_mm});
      edge.a = m;
    } else {
      edge.points.push_back(CenterlinePoint{nodes_[m], edge.points.back().radius_mm});
      edge.b = m;
    }
  }

  void move_node(std::size_t n, const glm::dvec3& p) {
    nodes_[n] = p;
    for (Edge& e : edges_) {
      if (!e.alive) continue;
      if (e.a == n) e.points.front().pos_mm = p;
      if (e.b == n) e.points.back().pos_mm = p;
    }
  }

 private:
  std::vector<glm::dvec3> nodes_;
  std::vector<Edge> edges_;
};

[[nodiscard]] double length_of(const std::vector<CenterlinePoint>& points) {
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) length += glm::length(points[k + 1].pos_mm - points[k].pos_mm);
  return length;
}

[[nodiscard]] std::string clean_name(const std::string& name) {
  std::string out;
  for (char ch : name) out += static_cast<unsigned char>(ch) < 0x20 ? ' ' : ch;
  const auto first = out.find_first_not_of(' ');
  if (first == std::string::npos) return {};
  return out.substr(first, out.find_last_not_of(' ') - first + 1);
}

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

// The representative radius of a node: the widest incident end.
[[nodiscard]] double node_radius(const Graph& g, const std::vector<std::size_t>& incident, std::size_t n) {
  double r = 0.0;
  for (std::size_t e : incident) {
    const Edge& edge = g.edges()[e];
    if (edge.a == n) r = std::max(r, edge.points.front().radius_mm);
    if (edge.b == n) r = std::max(r, edge.points.back().radius_mm);
  }
  return r;
}

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

// Orientation: depth-first from each component's root (its widest free end, or a node on a
// cycle), every edge in discovery order and pointing away from the root (back edges to the
// ancestor they close a cycle on).
class Orientation {
 public:
  // `inlet`: a free end that roots its piece (kNone: each piece's widest free end).
  Orientation(const Graph& g, std::size_t inlet)
      : forward(g.edges().size(), 1), g_(g), incident_(g.incidence()), state_(g.node_count(), 0),
        used_(g.edges().size(), 0), inlet_(inlet) {}

  void run(NetworkStats& stats) {
    for (std::size_t start = 0; start < g_.node_count(); ++start) {
      if (state_[start] != 0 || incident_[start].empty()) continue;
      walk(root_of(component(start), start), true);
      ++stats.components;
    }
  }

  std::vector<std::size_t> order;  // edges in discovery order
  std::vector<char> forward;       // points run a -> b (else reversed)

 private:
  [[nodiscard]] std::size_t other_end(std::size_t e, std::size_t n) const {
    return g_.edges()[e].a == n ? g_.edges()[e].b : g_.edges()[e].a;
  }

  // The component's nodes, to choose its root.
  [[nodiscard]] std::vector<std::size_t> component(std::size_t start) const {
    std::vector<std::size_t> members;
    std::vector<std::size_t> stack{start};
    std::vector<char> seen(g_.node_count(), 0);
    seen[start] = 1;
    while (!stack.empty()) {
      const std::size_t n = stack.back();
      stack.pop_back();
      members.push_back(n);
      for (std::size_t e : incident_[n]) {
        const std::size_t to = other_end(e, n);
        if (!seen[to]) {
          seen[to] = 1;
          stack.push_back(to);
        }
      }
    }
    return members;
  }

  // The widest free end; with none, a first walk finds a node on a cycle, the real one starts there.
  std::size_t root_of(const std::vector<std::size_t>& members, std::size_t start) {
    if (inlet_ != kNone && std::find(members.begin(), members.end(), inlet_) != members.end()) return inlet_;
    std::size_t root = kNone;
    double widest = -1.0;
    for (std::size_t n : members) {
      if (incident_[n].size() != 1) continue;
      const double r = node_radius(g_, incident_[n], n);
      if (r > widest) {
        widest = r;
        root = n;
      }
    }
    if (root != kNone) return root;
    const std::size_t on_cycle = walk(start, false);
    for (std::size_t n : members) state_[n] = 0;
    for (std::size_t n : members) {
      for (std::size_t e : incident_[n]) used_[e] = 0;
    }
    return on_cycle == kNone ? start : on_cycle;
  }

  // Iterative DFS from `root`; edges to a node on the stack (back edges) point to it. Returns the
  // first node a back edge reached (kNone: no cycle).
  std::size_t walk(std::size_t root, bool record) {
    std::size_t cycle_node = kNone;
    struct Frame {
      std::size_t node;
      std::size_t next = 0;
    };
    std::vector<Frame> stack{{root}};
    state_[root] = 1;
    while (!stack.empty()) {
      Frame& f = stack.back();
      if (f.next == incident_[f.node].size()) {
        state_[f.node] = 2;
        stack.pop_back();
        continue;
      }
      const std::size_t e = incident_[f.node][f.next++];
      if (used_[e]) continue;
      used_[e] = 1;
      const std::size_t from = f.node;
      const std::size_t to = other_end(e, from);
      if (record) {
        forward[e] = g_.edges()[e].a == from ? 1 : 0;
        order.push_back(e);
      }
      if (state_[to] == 0) {  // tree edge: from `from` to `to`
        state_[to] = 1;
        stack.push_back({to});  // may reallocate: `f` is not used after
      } else if (cycle_node == kNone) {  // back edge (an ancestor on the stack): from `from` up to `to`
        cycle_node = to;
      }
    }
    return cycle_node;
  }

  const Graph& g_;
  std::vector<std::vector<std::size_t>> incident_;
  std::vector<int> state_;  // 0 unseen, 1 on the stack, 2 done
  std::vector<char> used_;
  std::size_t inlet_;
};

// The free end nearest `p` (kNone: no free end) and its distance.
[[nodiscard]] std::size_t nearest_free_end(const Graph& g, const glm::dvec3& p, double& distance) {
  const auto incident = g.incidence();
  std::size_t best = kNone;
  distance = std::numeric_limits<double>::infinity();
  for (std::size_t n = 0; n < g.node_count(); ++n) {
    const double d = glm::length(g.node(n) - p);
    if (incident[n].size() == 1 && d < distance) {
      distance = d;
      best = n;
    }
  }
  return best;
}

// Segments in discovery order, with their end nodes after orientation; parents and children
// from the nodes they share. False (out.error set) for a junction no segment ends or starts at.
bool make_segments(Graph& g, const Orientation& orientation, NetworkBuild& out, NetworkStats& stats) {
  const std::size_t n_nodes = g.node_count();
  std::vector<std::size_t> start_node, end_node;
  for (std::size_t e : orientation.order) {
    Edge& edge = g.edges()[e];
    vessel::Segment s;
    s.id = static_cast<std::int32_t>(out.model.segments.size() + 1);
    s.name = clean_name(edge.name);
    s.points = edge.points;
    const bool forward = orientation.forward[e] != 0;
    if (!forward) std::reverse(s.points.begin(), s.points.end());
    start_node.push_back(forward ? edge.a : edge.b);
    end_node.push_back(forward ? edge.b : edge.a);
    out.model.segments.push_back(std::move(s));
  }
  std::vector<std::vector<std::size_t>> ending(n_nodes), starting(n_nodes);
  for (std::size_t i = 0; i < out.model.segments.size(); ++i) {
    ending[end_node[i]].push_back(i);
    starting[start_node[i]].push_back(i);
  }
  std::size_t used_nodes = 0;
  for (std::size_t n = 0; n < n_nodes; ++n) {
    const std::size_t ends = ending[n].size() + starting[n].size();
    if (ends == 0) continue;
    ++used_nodes;
    if (ends == 1) {
      ++stats.free_ends;
      continue;
    }
    ++stats.junctions;
    if (ending[n].empty() || starting[n].empty()) {
      out.error = "internal: junction without a segment ending or starting there";
      return false;
    }
    for (std::size_t in : ending[n]) {
      for (std::size_t o : starting[n]) {
        out.model.segments[in].children.push_back(out.model.segments[o].id);
        out.model.segments[o].parents.push_back(out.model.segments[in].id);
      }
    }
  }
  stats.cycles = out.model.segments.size() + stats.components - used_nodes;
  return true;
}

// Clean-up, orientation and HCLM segments (see the header).
NetworkBuild finish(Graph& g, NetworkStats stats, const Orient& orient) {
  NetworkBuild out;
  merge_collapsed(g);
  prune_stubs(g, stats);
  contract_short_branches(g, stats);
  split_self_loops(g);
  join_chains(g, stats);
  std::size_t inlet = kNone;
  double inlet_gap = 0.0;
  if (orient.inlet_mm) {
    inlet = nearest_free_end(g, *orient.inlet_mm, inlet_gap);
    if (inlet == kNone) {
      out.error = "--inlet: the network has no free end to be the inlet";
      return out;
    }
  }
  Orientation orientation(g, inlet);
  orientation.run(stats);
  if (!make_segments(g, orientation, out, stats)) return out;
  if (out.model.segments.empty()) out.error = "no vessel left: every polyline was a single point";
  out.stats = stats;
  if (out.ok() && orient.inlet_mm) out.oriented = inlet_note(out.model, *orient.inlet_mm, inlet_gap);
  if (out.ok() && orient.sac_mm) name_sac(out, *orient.sac_mm);
  return out;
}

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

}  // namespace

NetworkBuild build_network(const std::vector<Polyline>& polylines, const Orient& orient) {
  Graph g;
  NetworkStats stats;
  stats.polylines = polylines.size();
  for (const Polyline& line : polylines) {
    const auto& p = line.points;
    if (p.size() < 2) continue;
    const auto on_network = [&](std::size_t i) {
      if (g.edges().empty()) return false;
      return g.nearest(p[i].pos_mm).distance <= kOverlapRadii * p[i].radius_mm;
    };
    const std::size_t n = p.size();
    std::size_t lead = 0;  // points at the start lying on the network
    while (lead < n && on_network(lead)) ++lead;
    if (lead == n) {
      ++stats.duplicates;
      stats.shared_points += n;
      continue;
    }
    std::size_t trail = 0;  // ... and at the end
    while (trail < n - lead && on_network(n - 1 - trail)) ++trail;
    if (lead > 1 || trail > 1) ++stats.overlapping;
    stats.shared_points += (lead > 1 ? lead - 1 : 0) + (trail > 1 ? trail - 1 : 0);
    // The new branch: from the last shared point's place on the network (or a new free end) to
    // the first shared point's place at the end (or a new free end).
    std::vector<CenterlinePoint> points;
    std::size_t from = kNone;
    if (lead > 0) {
      const Location at = g.nearest(p[lead - 1].pos_mm);
      from = g.attach(at, p[lead - 1].radius_mm);
      points.push_back({g.node(from), p[lead].radius_mm});  // with the branch's own radius
    } else {
      from = g.add_node(p[0].pos_mm);
      points.push_back(p[0]);
    }
    const std::size_t last_new = trail > 0 ? n - trail : n;  // one past the last point of our own
    for (std::size_t i = lead == 0 ? 1 : lead; i < last_new; ++i) points.push_back(p[i]);
    std::size_t to = kNone;
    if (trail > 0) {
      const Location at = g.nearest(p[n - trail].pos_mm);
      to = g.attach(at, p[n - trail].radius_mm);
      points.push_back({g.node(to), p[n - trail - 1].radius_mm});
    } else if (glm::length(points.back().pos_mm - g.node(from)) <= kOverlapRadii * points.back().radius_mm) {
      to = from;  // a closed curve: back to its own start
    } else {
      to = g.add_node(points.back().pos_mm);
    }
    if (points.size() < 2 || (from == to && points.size() < 3)) continue;
    g.add_edge(std::move(points), from, to, line.name);
  }
  join_near_ends(g, stats);
  return finish(g, stats, orient);
}

NetworkBuild build_network(const std::vector<Branch>& branches, const Orient& orient) {
  Graph g;
  NetworkStats stats;
  stats.polylines = branches.size();
  std::map<std::size_t, std::size_t> node_of;  // given id -> graph node
  const auto node = [&](std::size_t id, const glm::dvec3& p) {
    const auto [it, inserted] = node_of.try_emplace(id, 0);
    if (inserted) it->second = g.add_node(p);
    return it->second;
  };
  for (const Branch& branch : branches) {
    if (branch.line.points.size() < 2) continue;
    const std::size_t a = node(branch.from, branch.line.points.front().pos_mm);
    const std::size_t b = node(branch.to, branch.line.points.back().pos_mm);
    g.add_edge(branch.line.points, a, b, branch.line.name);
  }
  return finish(g, stats, orient);
}

}  // namespace cathbox::vessel_import
