#pragma once
// The network being built (network_builder.hpp): nodes and the polylines (edges) between them,
// with the nearest-place search and the splits, bridges and moves the builder's steps make.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <string>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "vessel_import/network_builder.hpp"

namespace cathbox::vessel_import::detail {

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

[[nodiscard]] inline double length_of(const std::vector<CenterlinePoint>& points) {
  double length = 0.0;
  for (std::size_t k = 0; k + 1 < points.size(); ++k) length += glm::length(points[k + 1].pos_mm - points[k].pos_mm);
  return length;
}

// The representative radius of a node: the widest incident end.
[[nodiscard]] inline double node_radius(const Graph& g, const std::vector<std::size_t>& incident, std::size_t n) {
  double r = 0.0;
  for (std::size_t e : incident) {
    const Edge& edge = g.edges()[e];
    if (edge.a == n) r = std::max(r, edge.points.front().radius_mm);
    if (edge.b == n) r = std::max(r, edge.points.back().radius_mm);
  }
  return r;
}

}  // namespace cathbox::vessel_import::detail
