#include "network_segments.hpp"

#include <algorithm>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>

namespace cathbox::vessel_import::detail {

namespace {

[[nodiscard]] std::string clean_name(const std::string& name) {
  std::string out;
  for (char ch : name) out += static_cast<unsigned char>(ch) < 0x20 ? ' ' : ch;
  const auto first = out.find_first_not_of(' ');
  if (first == std::string::npos) return {};
  return out.substr(first, out.find_last_not_of(' ') - first + 1);
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

}  // namespace

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

namespace {

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

}  // namespace

bool oriented_segments(Graph& g, std::size_t inlet, NetworkBuild& out, NetworkStats& stats) {
  Orientation orientation(g, inlet);
  orientation.run(stats);
  return make_segments(g, orientation, out, stats);
}

}  // namespace cathbox::vessel_import::detail
