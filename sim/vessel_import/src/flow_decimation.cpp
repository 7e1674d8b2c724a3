// Shortest-edge-first decimation of the flow's copy of the lumen (flow_decimation.hpp).
//
// Why not CGAL's Surface_mesh_simplification::edge_collapse with Edge_length_cost and
// Midpoint_placement, which gives the same order: after every collapse it recomputes the cost of
// every edge around every neighbour of the kept vertex (~30 edges), each through an edge profile
// that gathers the edge's link and triangles into vectors, and keeps them in a mutable priority
// queue, because its costs may depend on the neighbourhood. An edge's length depends on its two
// ends only: a collapse changes the lengths of the edges at the kept vertex alone. Here those are
// pushed again with a new stamp (older entries of the same edge are skipped when they come up),
// and edges that were refused earlier are queued again when a collapse changes their
// neighbourhood, as CGAL does. On the 293k-triangle head-and-neck lumen (to 25,000 triangles) the
// flow stage, decimation included, went from 4.5-5.4 s to 1.5 s of CPU at a load of 13-15, the
// graph the same (sim/vessel_import/README.md, "Speed").
#include "flow_decimation.hpp"

#include <cstdint>
#include <queue>
#include <vector>

#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/boost/graph/graph_traits_Surface_mesh.h>
#include <CGAL/boost/graph/iterator.h>

namespace cathbox::vessel_import {
namespace {

using Point = FlowMesh::Point;
using Vector = CGAL::Exact_predicates_inexact_constructions_kernel::Vector_3;
using Vertex = FlowMesh::Vertex_index;
using Edge = FlowMesh::Edge_index;
using Halfedge = FlowMesh::Halfedge_index;

struct Candidate {
  double length2;
  std::uint32_t edge;
  std::uint32_t stamp;
};
// std::priority_queue keeps the greatest on top: "greater" puts the shortest, then the lowest
// edge index, there.
struct Later {
  bool operator()(const Candidate& a, const Candidate& b) const {
    return a.length2 > b.length2 || (a.length2 == b.length2 && a.edge > b.edge);
  }
};

class Collapser {
 public:
  explicit Collapser(FlowMesh& mesh) : mesh_(mesh), stamp_(mesh.num_edges(), 0), queued_(mesh.num_edges(), false) {
    std::vector<Candidate> all;
    all.reserve(mesh.number_of_edges());
    for (Edge e : mesh_.edges()) all.push_back(candidate(e));
    queue_ = Queue(Later(), std::move(all));
  }

  void run(std::size_t faces) {
    while (mesh_.number_of_faces() > faces && !queue_.empty()) {
      const Candidate c = queue_.top();
      queue_.pop();
      const Edge e(c.edge);
      if (mesh_.is_removed(e) || c.stamp != stamp_[c.edge]) continue;  // gone, or queued again since
      queued_[c.edge] = false;
      if (!CGAL::Euler::does_satisfy_link_condition(e, mesh_)) continue;
      const Halfedge h = mesh_.halfedge(e);
      const Vertex v0 = mesh_.source(h);
      const Vertex v1 = mesh_.target(h);
      const Point middle = CGAL::midpoint(mesh_.point(v0), mesh_.point(v1));
      if (turns_a_triangle_over(v0, v1, middle)) continue;
      const Vertex kept = CGAL::Euler::collapse_edge(e, mesh_);
      mesh_.point(kept) = middle;
      queue_around(kept);
    }
  }

 private:
  using Queue = std::priority_queue<Candidate, std::vector<Candidate>, Later>;

  Candidate candidate(Edge e) {
    const Halfedge h = mesh_.halfedge(e);
    queued_[e.idx()] = true;
    return {CGAL::squared_distance(mesh_.point(mesh_.source(h)), mesh_.point(mesh_.target(h))),
            static_cast<std::uint32_t>(e.idx()), ++stamp_[e.idx()]};
  }

  // The kept vertex's edges have new lengths; the edges around its neighbours that were refused
  // (link condition, a triangle turned over) may pass now.
  void queue_around(Vertex kept) {
    for (Halfedge h : CGAL::halfedges_around_target(kept, mesh_)) queue_.push(candidate(mesh_.edge(h)));
    for (Vertex v : CGAL::vertices_around_target(kept, mesh_)) {
      for (Halfedge h : CGAL::halfedges_around_target(v, mesh_)) {
        const Edge e = mesh_.edge(h);
        if (!queued_[e.idx()]) queue_.push(candidate(e));
      }
    }
  }

  // Whether a triangle at v0 or v1 (other than the two on the edge, which vanish) would face the
  // other way, or have no area, with that vertex moved to `middle`.
  [[nodiscard]] bool turns_a_triangle_over(Vertex v0, Vertex v1, const Point& middle) const {
    for (const Vertex moved : {v0, v1}) {
      for (Halfedge h : CGAL::halfedges_around_target(moved, mesh_)) {
        if (mesh_.is_border(h)) continue;
        const Vertex b = mesh_.target(mesh_.next(h));
        const Vertex c = mesh_.source(h);
        if (b == v0 || b == v1 || c == v0 || c == v1) continue;
        const Point& pa = mesh_.point(moved);
        const Point& pb = mesh_.point(b);
        const Point& pc = mesh_.point(c);
        const Vector before = CGAL::cross_product(pb - pa, pc - pa);
        const Vector after = CGAL::cross_product(pb - middle, pc - middle);
        if (!(before * after > 0.0)) return true;
      }
    }
    return false;
  }

  FlowMesh& mesh_;
  std::vector<std::uint32_t> stamp_;  // per edge: the stamp of its one live queue entry
  std::vector<bool> queued_;          // per edge: has a live queue entry
  Queue queue_;
};

}  // namespace

void collapse_shortest_edges(FlowMesh& mesh, std::size_t faces) {
  if (mesh.number_of_faces() > faces) Collapser(mesh).run(faces);
  mesh.collect_garbage();
}

}  // namespace cathbox::vessel_import
