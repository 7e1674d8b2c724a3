#include "session/centerline_path.hpp"

#include <algorithm>
#include <limits>
#include <queue>

#include <glm/geometric.hpp>

namespace cathbox::session {
namespace {

// Graph nodes: 2*s = start of segment s, 2*s+1 = its end. Edges: along a segment (its length),
// and free (length 0) between ends that meet at a junction.
struct Graph {
  std::vector<std::vector<std::pair<std::size_t, double>>> adj;
};

std::vector<double> arc_lengths(const PathSegment& s) {
  std::vector<double> a(s.points_mm.size(), 0.0);
  for (std::size_t i = 1; i < s.points_mm.size(); ++i) {
    a[i] = a[i - 1] + static_cast<double>(glm::distance(s.points_mm[i], s.points_mm[i - 1]));
  }
  return a;
}

double length_of(const PathSegment& s) {
  const std::vector<double> a = arc_lengths(s);
  return a.empty() ? 0.0 : a.back();
}

Graph build_graph(const std::vector<PathSegment>& segs) {
  Graph g;
  g.adj.resize(2 * segs.size());
  auto link = [&](std::size_t a, std::size_t b, double w) {
    g.adj[a].emplace_back(b, w);
    g.adj[b].emplace_back(a, w);
  };
  for (std::size_t s = 0; s < segs.size(); ++s) {
    link(2 * s, 2 * s + 1, length_of(segs[s]));
    for (std::size_t c : segs[s].children) {
      if (c < segs.size()) link(2 * s + 1, 2 * c, 0.0);  // parent end = child start
    }
  }
  return g;
}

std::vector<double> dijkstra(const Graph& g, const std::vector<std::pair<std::size_t, double>>& sources,
                             std::vector<std::size_t>& previous) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> dist(g.adj.size(), inf);
  previous.assign(g.adj.size(), std::numeric_limits<std::size_t>::max());
  using Item = std::pair<double, std::size_t>;
  std::priority_queue<Item, std::vector<Item>, std::greater<>> queue;
  for (const auto& [node, d] : sources) {
    if (node < dist.size() && d < dist[node]) {
      dist[node] = d;
      queue.emplace(d, node);
    }
  }
  while (!queue.empty()) {
    const auto [d, n] = queue.top();
    queue.pop();
    if (d > dist[n]) continue;
    for (const auto& [m, w] : g.adj[n]) {
      if (d + w < dist[m]) {
        dist[m] = d + w;
        previous[m] = n;
        queue.emplace(dist[m], m);
      }
    }
  }
  return dist;
}

// Points of segment s from fraction f0 to f1 (either direction), both ends included.
void append_span(const PathSegment& s, double f0, double f1, std::vector<glm::vec3>& out) {
  const std::vector<double> a = arc_lengths(s);
  if (a.empty()) return;
  const double total = a.back();
  const double d0 = std::clamp(f0, 0.0, 1.0) * total;
  const double d1 = std::clamp(f1, 0.0, 1.0) * total;
  out.push_back(CenterlinePath::point_at(s, f0));
  if (d1 >= d0) {
    for (std::size_t i = 0; i < a.size(); ++i) {
      if (a[i] > d0 && a[i] < d1) out.push_back(s.points_mm[i]);
    }
  } else {
    for (std::size_t i = a.size(); i-- > 0;) {
      if (a[i] < d0 && a[i] > d1) out.push_back(s.points_mm[i]);
    }
  }
  out.push_back(CenterlinePath::point_at(s, f1));
}

}  // namespace

glm::vec3 CenterlinePath::point_at(const PathSegment& s, double fraction) {
  if (s.points_mm.empty()) return glm::vec3(0.0F);
  const std::vector<double> a = arc_lengths(s);
  const double d = std::clamp(fraction, 0.0, 1.0) * a.back();
  for (std::size_t i = 1; i < a.size(); ++i) {
    if (a[i] >= d) {
      const double len = a[i] - a[i - 1];
      const float t = len > 0.0 ? static_cast<float>((d - a[i - 1]) / len) : 0.0F;
      return s.points_mm[i - 1] + t * (s.points_mm[i] - s.points_mm[i - 1]);
    }
  }
  return s.points_mm.back();
}

PathPoint CenterlinePath::nearest(const std::vector<PathSegment>& segs, const glm::vec3& p) {
  PathPoint best;
  float best_d2 = std::numeric_limits<float>::max();
  for (std::size_t s = 0; s < segs.size(); ++s) {
    const std::vector<double> a = arc_lengths(segs[s]);
    const double total = a.empty() ? 0.0 : a.back();
    for (std::size_t i = 0; i + 1 < segs[s].points_mm.size(); ++i) {
      const glm::vec3 q0 = segs[s].points_mm[i];
      const glm::vec3 e = segs[s].points_mm[i + 1] - q0;
      const float len2 = glm::dot(e, e);
      const float t = len2 > 0.0F ? std::clamp(glm::dot(p - q0, e) / len2, 0.0F, 1.0F) : 0.0F;
      const glm::vec3 d = q0 + t * e - p;
      if (glm::dot(d, d) < best_d2) {
        best_d2 = glm::dot(d, d);
        best.segment = s;
        best.fraction = total > 0.0 ? (a[i] + static_cast<double>(t) * (a[i + 1] - a[i])) / total : 0.0;
      }
    }
  }
  return best;
}

double CenterlinePath::length_mm(const std::vector<glm::vec3>& polyline) {
  double total = 0.0;
  for (std::size_t i = 1; i < polyline.size(); ++i) total += static_cast<double>(glm::distance(polyline[i], polyline[i - 1]));
  return total;
}

std::vector<glm::vec3> CenterlinePath::between(const std::vector<PathSegment>& segs, const PathPoint& from,
                                               const PathPoint& to, std::vector<std::size_t>* segments_out) {
  std::vector<glm::vec3> out;
  std::vector<std::size_t> visited;
  if (from.segment >= segs.size() || to.segment >= segs.size()) return out;
  if (from.segment == to.segment) {
    append_span(segs[from.segment], from.fraction, to.fraction, out);
    if (segments_out != nullptr) *segments_out = {from.segment};
    return out;
  }
  const Graph g = build_graph(segs);
  const double from_len = length_of(segs[from.segment]);
  const double to_len = length_of(segs[to.segment]);
  std::vector<std::size_t> prev;
  const std::vector<double> dist = dijkstra(
      g, {{2 * from.segment, from.fraction * from_len}, {2 * from.segment + 1, (1.0 - from.fraction) * from_len}}, prev);
  // Reach the target segment at its start or its end, whichever totals less.
  const double via_start = dist[2 * to.segment] + to.fraction * to_len;
  const double via_end = dist[2 * to.segment + 1] + (1.0 - to.fraction) * to_len;
  if (!(std::min(via_start, via_end) < std::numeric_limits<double>::infinity())) return out;
  std::size_t node = via_start <= via_end ? 2 * to.segment : 2 * to.segment + 1;
  std::vector<std::size_t> chain = {node};
  while (prev[node] != std::numeric_limits<std::size_t>::max()) {
    node = prev[node];
    chain.push_back(node);
  }
  std::reverse(chain.begin(), chain.end());
  // The first node is an end of the entry segment: run there from the entry point.
  append_span(segs[from.segment], from.fraction, chain.front() % 2 == 0 ? 0.0 : 1.0, out);
  visited.push_back(from.segment);
  for (std::size_t k = 1; k < chain.size(); ++k) {
    const std::size_t a = chain[k - 1];
    const std::size_t b = chain[k];
    if (a / 2 == b / 2) {
      append_span(segs[a / 2], a % 2 == 0 ? 0.0 : 1.0, b % 2 == 0 ? 0.0 : 1.0, out);
      if (visited.back() != a / 2) visited.push_back(a / 2);
    }
  }
  append_span(segs[to.segment], chain.back() % 2 == 0 ? 0.0 : 1.0, to.fraction, out);
  if (visited.back() != to.segment) visited.push_back(to.segment);
  if (segments_out != nullptr) *segments_out = std::move(visited);
  // Drop repeated points (junction hops give duplicates).
  out.erase(std::unique(out.begin(), out.end(),
                        [](const glm::vec3& p, const glm::vec3& q) { return glm::distance(p, q) < 1e-6F; }),
            out.end());
  return out;
}

std::optional<PathPoint> CenterlinePath::farthest_leaf(const std::vector<PathSegment>& segs, const PathPoint& from) {
  if (from.segment >= segs.size()) return std::nullopt;
  const Graph g = build_graph(segs);
  const double from_len = length_of(segs[from.segment]);
  std::vector<std::size_t> prev;
  const std::vector<double> dist = dijkstra(
      g, {{2 * from.segment, from.fraction * from_len}, {2 * from.segment + 1, (1.0 - from.fraction) * from_len}}, prev);
  std::optional<PathPoint> best;
  double best_d = -1.0;
  for (std::size_t s = 0; s < segs.size(); ++s) {
    if (!segs[s].children.empty() || s == from.segment) continue;
    const double d = dist[2 * s + 1];
    if (d < std::numeric_limits<double>::infinity() && d > best_d) {
      best_d = d;
      best = PathPoint{s, 1.0};
    }
  }
  return best;
}

}  // namespace cathbox::session
