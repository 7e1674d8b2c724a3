// Surface → repaired closed lumen → mean curvature flow skeleton → branches with radii. The only
// file that includes CGAL (surface_import.hpp says what each step does and why).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <limits>
#include <map>

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>
#include <glm/geometric.hpp>

#include "vessel/point_range.hpp"
#include "vessel_import/surface_import.hpp"

// CGAL 5.5's flow keeps the edges it will collapse (`collapse_short_edges`) in a
// std::set<edge_descriptor> of its Polyhedron meso-skeleton, whose operator< compares the
// halfedges' addresses: which short edge collapses first, and so which thin branches survive,
// followed the heap layout (another build, another file order, another process: another graph).
// Here the set orders edges by their halfedges' ids instead, which the flow loop below numbers in
// the mesh's own list order before every collapse pass (the pass creates no halfedge, so the ids
// stay unique while the set lives).
namespace cathbox::vessel_import::skeleton_order {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<CGAL::Surface_mesh<Kernel::Point_3>>;
using Meso = Skeletonization::Meso_skeleton;
using MesoEdge = boost::graph_traits<Meso>::edge_descriptor;
}  // namespace cathbox::vessel_import::skeleton_order

namespace cathbox::vessel_import::skeleton_order {
// A cell's circumcentre in double, or through exact numbers where the cell is so flat that double
// rounding would move it (the generator's tubes have rings of cospherical points: such slivers
// are common, and an exactly flat one in double has no circumcentre at all).
inline Kernel::Point_3 circumcentre(const Kernel::Point_3& a, const Kernel::Point_3& b, const Kernel::Point_3& c,
                                    const Kernel::Point_3& d) {
  const Kernel::Vector_3 u = b - a;
  const Kernel::Vector_3 v = c - a;
  const Kernel::Vector_3 w = d - a;
  const double longest = std::max({u.squared_length(), v.squared_length(), w.squared_length()});
  if (std::abs(u * CGAL::cross_product(v, w)) > 1e-8 * longest * std::sqrt(longest)) return CGAL::circumcenter(a, b, c, d);
  using Exact = CGAL::Exact_predicates_exact_constructions_kernel;
  const CGAL::Cartesian_converter<Kernel, Exact> exact;
  const Exact::Point_3 e = CGAL::circumcenter(exact(a), exact(b), exact(c), exact(d));
  return {CGAL::to_double(e.x()), CGAL::to_double(e.y()), CGAL::to_double(e.z())};
}
}  // namespace cathbox::vessel_import::skeleton_order

// The flow's Voronoi poles (Amenta and Bern 1999, as CGAL uses them: for each vertex, the
// circumcentre of a Delaunay cell around it lying deepest inside along its normal) pull the
// meso-skeleton towards the medial axis. CGAL 5.5 triangulates the vertices in the
// exact-constructions kernel and rounds every circumcentre to double: on the head-and-neck lumen
// (117k vertices) the flow's first step took 4.6 s of CPU, here 3.6 s. Here the same
// triangulation (exact predicates either way) in the inexact-constructions kernel, each
// circumcentre in double unless its cell is nearly flat (circumcentre() above); a pole outside
// the surface is ignored by the flow either way.
template <>
void cathbox::vessel_import::skeleton_order::Skeletonization::compute_voronoi_pole() {
  compute_vertex_normal();
  using InexactVb = CGAL::Triangulation_vertex_base_with_info_3<vertex_descriptor, Traits>;
  using InexactCb = CGAL::Delaunay_triangulation_cell_base_3<Traits>;
  using InexactDelaunay = CGAL::Delaunay_triangulation_3<Traits, CGAL::Triangulation_data_structure_3<InexactVb, InexactCb>>;
  std::vector<std::pair<Point, vertex_descriptor>> points;
  points.reserve(num_vertices(m_tmesh));
  for (vertex_descriptor v : vertices(m_tmesh)) points.emplace_back(get(m_tmesh_point_pmap, v), v);
  const InexactDelaunay delaunay(points.begin(), points.end());
  std::vector<double> depth(num_vertices(m_tmesh), 0.0);  // of the pole, along the inward normal
  if (delaunay.dimension() == 3) {
    for (auto cell = delaunay.finite_cells_begin(); cell != delaunay.finite_cells_end(); ++cell) {
      const Point centre = cathbox::vessel_import::skeleton_order::circumcentre(
          cell->vertex(0)->point(), cell->vertex(1)->point(), cell->vertex(2)->point(), cell->vertex(3)->point());
      for (int i = 0; i < 4; ++i) {
        const vertex_descriptor v = cell->vertex(i)->info();
        const std::size_t id = get(m_vertex_id_pmap, v);
        const double t = -((centre - get(m_tmesh_point_pmap, v)) * m_normals[id]);
        if (t > depth[id]) {
          depth[id] = t;
          v->pole = centre;
        }
      }
    }
  }
  // A vertex at another's position (inserted once) takes that one's pole.
  for (const auto& [p, v] : points) {
    if (depth[get(m_vertex_id_pmap, v)] > 0.0) continue;
    typename InexactDelaunay::Locate_type type{};
    int li = 0;
    int lj = 0;
    const auto cell = delaunay.locate(p, type, li, lj);
    if (type == InexactDelaunay::VERTEX) v->pole = cell->vertex(li)->info()->pole;
  }
  m_are_poles_computed = true;
}

// One step of the flow (CGAL's contract_geometry: the least-squares system of the Laplacian, the
// attraction to the current positions and to the poles, solved through its normal equations), with
// two changes that leave the system and so the result the same: whether a vertex's pole is inside
// the meso-skeleton is tested once per step (CGAL 5.5 tests it in assemble_LHS and again in
// assemble_RHS, each building an AABB tree of the meso-skeleton and shooting a ray per vertex),
// and the vertices' rows come from a vector instead of a std::map lookup per matrix entry.
template <>
void cathbox::vessel_import::skeleton_order::Skeletonization::contract_geometry() {
  update_vertex_id();  // m_new_id, as CGAL keeps it
  compute_edge_weight();
  const int nver = static_cast<int>(num_vertices(m_tmesh));
  if (m_is_medially_centered && !m_are_poles_computed) compute_voronoi_pole();
  std::vector<int> row(static_cast<std::size_t>(m_vertex_id_count), 0);
  std::vector<vertex_descriptor> order;
  order.reserve(static_cast<std::size_t>(nver));
  for (vertex_descriptor vd : vertices(m_tmesh)) {
    row[get(m_vertex_id_pmap, vd)] = static_cast<int>(order.size());
    order.push_back(vd);
  }
  std::vector<char> attracted(order.size(), 0);  // to its pole: not fixed, pole known and inside
  if (m_is_medially_centered) {
    const Side_of_triangle_mesh<mTriangleMesh, Traits> test_inside(m_tmesh);
    for (std::size_t i = 0; i < order.size(); ++i) {
      const vertex_descriptor vd = order[i];
      attracted[i] = !vd->is_fixed && static_cast<int>(get(m_vertex_id_pmap, vd)) < m_max_id &&
                     test_inside(vd->pole) == CGAL::ON_BOUNDED_SIDE;
    }
  }
  const int nrows = nver * (m_is_medially_centered ? 3 : 2);
  typename SolverTraits::Matrix A(nrows, nver);
  typename SolverTraits::Vector X(nver), Bx(nrows);
  typename SolverTraits::Vector Y(nver), By(nrows);
  typename SolverTraits::Vector Z(nver), Bz(nrows);
  for (int i = 0; i < nver; ++i) {
    const vertex_descriptor vd = order[static_cast<std::size_t>(i)];
    const double oh = vd->is_fixed ? 1.0 / m_zero_TH : m_omega_H;
    const double op = attracted[static_cast<std::size_t>(i)] != 0 ? m_omega_P : 0.0;
    A.set_coef(i + nver, i, oh, true);
    if (op != 0.0) A.set_coef(i + nver * 2, i, op, true);
    const Point& p = get(m_tmesh_point_pmap, vd);
    Bx[i] = 0;
    By[i] = 0;
    Bz[i] = 0;
    Bx[i + nver] = get_x(p) * oh;
    By[i + nver] = get_y(p) * oh;
    Bz[i + nver] = get_z(p) * oh;
    if (m_is_medially_centered) {
      Bx[i + nver * 2] = get_x(vd->pole) * op;
      By[i + nver * 2] = get_y(vd->pole) * op;
      Bz[i + nver * 2] = get_z(vd->pole) * op;
    }
  }
  for (int i = 0; i < nver; ++i) {  // the Laplacian rows
    const vertex_descriptor vd = order[static_cast<std::size_t>(i)];
    const double L = vd->is_fixed ? 0.0 : 1.0;
    double diagonal = 0;
    for (edge_descriptor ed : in_edges(vd, m_tmesh)) {
      const double wij = m_edge_weight[get(m_hedge_id_pmap, halfedge(ed, m_tmesh))] * 2.0;
      A.set_coef(i, row[get(m_vertex_id_pmap, source(ed, m_tmesh))], wij * L, true);
      diagonal += -wij;
    }
    A.set_coef(i, i, diagonal, true);
  }
  m_solver.normal_equation_factor(A);
  m_solver.normal_equation_solver(Bx, X);
  m_solver.normal_equation_solver(By, Y);
  m_solver.normal_equation_solver(Bz, Z);
  for (int i = 0; i < nver; ++i) {
    put(m_tmesh_point_pmap, order[static_cast<std::size_t>(i)], m_traits.construct_point_3_object()(X[i], Y[i], Z[i]));
  }
}

template <>
struct std::less<cathbox::vessel_import::skeleton_order::MesoEdge> {
  bool operator()(const cathbox::vessel_import::skeleton_order::MesoEdge& a,
                  const cathbox::vessel_import::skeleton_order::MesoEdge& b) const {
    return key(a) < key(b);
  }
  static std::size_t key(const cathbox::vessel_import::skeleton_order::MesoEdge& e) {
    return std::min(e.halfedge()->id(), e.halfedge()->opposite()->id());
  }
};

namespace cathbox::vessel_import {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Mesh = CGAL::Surface_mesh<Point>;
using VertexIndex = Mesh::Vertex_index;
using HalfedgeIndex = Mesh::Halfedge_index;
using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<Mesh>;
using Skeleton = Skeletonization::Skeleton;
using SkeletonVertex = boost::graph_traits<Skeleton>::vertex_descriptor;
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh>;
using Tree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, Primitive>>;

[[nodiscard]] glm::dvec3 to_glm(const Point& p) { return {p.x(), p.y(), p.z()}; }

[[nodiscard]] std::string mm(double v) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.3g mm", v);
  return buffer;
}

// Polygons of more than three corners as fans from their first corner. Surfaces come as
// triangles or as the convex quads of structured meshes, for which a fan is exact; a concave
// polygon's fan overlaps itself and the self-intersection check refuses it. (CGAL's
// triangulate_faces runs a constrained Delaunay triangulation per polygon instead, which on a
// self-crossing polygon did not finish: fuzz_vessel_import_polygon_cells.)
[[nodiscard]] std::vector<std::vector<std::size_t>> fan_triangles(const std::vector<std::vector<std::size_t>>& polygons) {
  std::vector<std::vector<std::size_t>> triangles;
  triangles.reserve(polygons.size());
  for (const std::vector<std::size_t>& polygon : polygons) {
    for (std::size_t k = 1; k + 1 < polygon.size(); ++k) triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
  }
  return triangles;
}

class SurfaceImporter {
 public:
  SurfaceImporter(std::string_view file, const SurfaceOptions& options) : file_(file), options_(options) {}

  SurfaceImport run(PolygonSoup soup) {
    out_.stats.polygons_read = soup.polygons.size();
    out_.stats.points_read = soup.points.size();
    if (soup.polygons.empty()) return fail("not a surface: no polygons");
    SurfaceStats::Seconds& seconds = out_.stats.seconds;
    std::clock_t start = std::clock();
    const auto lap = [&start]() {
      const std::clock_t now = std::clock();
      const double elapsed = static_cast<double>(now - start) / CLOCKS_PER_SEC;
      start = now;
      return elapsed;
    };
    const bool repaired = to_mesh(std::move(soup)) && keep_one_component() && cap_open_ends();
    seconds.repair = lap();
    if (!repaired || !check_lumen()) return std::move(out_);
    canonicalise();
    seconds.check = lap();
    if (!skeletonise(lap)) return std::move(out_);
    keep_lumen();
    seconds.centre += lap();
    return std::move(out_);
  }

 private:
  SurfaceImport fail(std::string message) {
    out_.errors.push_back({file_, 0, 0, std::move(message)});
    return std::move(out_);
  }
  bool refuse(std::string message) {
    out_.errors.push_back({file_, 0, 0, std::move(message)});
    return false;
  }

  // The soup in mm, merged, oriented and made a triangle mesh.
  bool to_mesh(PolygonSoup soup) {
    std::vector<Point> points;
    points.reserve(soup.points.size());
    for (std::size_t i = 0; i < soup.points.size(); ++i) {
      const glm::dvec3 p = soup.points[i] * options_.unit_mm;
      if (std::string problem = vessel::point_range_problem(p, 0.0); !problem.empty()) {
        return refuse("vertex " + std::to_string(i) + ": " + problem);
      }
      points.emplace_back(p.x, p.y, p.z);
    }
    for (std::size_t f = 0; f < soup.polygons.size(); ++f) {
      for (std::size_t index : soup.polygons[f]) {
        if (index >= points.size()) {
          return refuse("polygon " + std::to_string(f) + " uses vertex " + std::to_string(index) + " of " +
                        std::to_string(points.size()));
        }
      }
    }
    const std::size_t points_before = points.size();
    const std::size_t polygons_before = soup.polygons.size();
    PMP::repair_polygon_soup(points, soup.polygons);
    out_.stats.points_merged = points_before - points.size();
    out_.stats.polygons_dropped = polygons_before - soup.polygons.size();
    if (soup.polygons.empty()) return refuse("not a surface: every polygon is degenerate");
    soup.polygons = fan_triangles(soup.polygons);
    // A soup that is already a consistently wound manifold (every directed edge once, as a
    // mesher or a segmentation writes it) is left as it is: orienting it would change nothing
    // and cost as much as the check. Orienting duplicates the points where edges are shared by
    // more than two polygons; what is still not a polygon mesh after that (e.g. a fan diagonal
    // that a neighbour already has as an edge) would build an invalid halfedge structure.
    if (!PMP::is_polygon_soup_a_polygon_mesh(soup.polygons)) {
      PMP::orient_polygon_soup(points, soup.polygons);
      if (!PMP::is_polygon_soup_a_polygon_mesh(soup.polygons)) {
        return refuse("not a surface: the polygons do not form a manifold mesh even after orienting");
      }
    }
    PMP::polygon_soup_to_polygon_mesh(points, soup.polygons, mesh_);
    return true;
  }

  bool keep_one_component() {
    auto component = mesh_.add_property_map<Mesh::Face_index, std::size_t>("f:component", 0).first;
    const std::size_t count = PMP::connected_components(mesh_, component);
    out_.stats.components = count;
    if (count <= 1) return true;
    std::vector<std::size_t> faces(count, 0);
    for (Mesh::Face_index f : mesh_.faces()) ++faces[component[f]];
    const std::size_t largest = *std::max_element(faces.begin(), faces.end());
    if (!options_.keep_largest) {
      return refuse(std::to_string(count) + " disconnected pieces (the largest " + std::to_string(largest) + " of " +
                    std::to_string(mesh_.number_of_faces()) + " triangles); give --largest to keep only it");
    }
    PMP::keep_largest_connected_components(mesh_, 1);
    mesh_.collect_garbage();
    out_.stats.components_dropped = count - 1;
    return true;
  }

  // Every border cycle is an inlet or outlet the segmentation cut: recorded, then capped.
  bool cap_open_ends() {
    std::vector<HalfedgeIndex> borders;
    PMP::extract_boundary_cycles(mesh_, std::back_inserter(borders));
    for (HalfedgeIndex h : borders) {
      OpenEnd end;
      glm::dvec3 sum(0.0);
      std::vector<glm::dvec3> ring;
      for (HalfedgeIndex e : CGAL::halfedges_around_face(h, mesh_)) ring.push_back(to_glm(mesh_.point(mesh_.target(e))));
      for (const glm::dvec3& p : ring) sum += p;
      end.centre_mm = sum / static_cast<double>(ring.size());
      for (const glm::dvec3& p : ring) end.radius_mm += glm::length(p - end.centre_mm) / static_cast<double>(ring.size());
      end.border_vertices = ring.size();
      std::vector<Mesh::Face_index> patch;
      PMP::triangulate_hole(mesh_, h, std::back_inserter(patch));
      if (patch.empty()) {
        return refuse("an open end of " + std::to_string(ring.size()) + " border vertices near (" +
                      mm(end.centre_mm.x) + ", " + mm(end.centre_mm.y) + ", " + mm(end.centre_mm.z) +
                      ") could not be capped");
      }
      out_.stats.open_ends.push_back(end);
    }
    return true;
  }

  bool check_lumen() {
    if (!CGAL::is_closed(mesh_)) return refuse("no closed lumen: the surface still has borders after capping its open ends");
    if (PMP::does_self_intersect(mesh_)) {
      std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
      PMP::self_intersections(mesh_, std::back_inserter(pairs));
      const glm::dvec3 at = to_glm(mesh_.point(mesh_.target(mesh_.halfedge(pairs.front().first))));
      return refuse("self-intersections beyond repair: " + std::to_string(pairs.size()) +
                    " pairs of triangles cross, the first near (" + mm(at.x) + ", " + mm(at.y) + ", " + mm(at.z) + ")");
    }
    if (!PMP::is_outward_oriented(mesh_)) PMP::reverse_face_orientations(mesh_);
    CGAL::Bbox_3 box;
    for (VertexIndex v : mesh_.vertices()) box += mesh_.point(v).bbox();
    out_.stats.extent_mm = std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()});
    out_.stats.triangles = mesh_.number_of_faces();
    return true;
  }

  // The lumen in an order of its geometry's own, not the file's: vertices sorted by position,
  // each triangle started at its smallest vertex (its winding kept), triangles sorted. The flow's
  // greedy steps (edge collapses, face splits, degeneracies) visit the mesh in its order and the
  // branches they leave depend on it: the head-and-neck tree's STL gave 29, 31 or 37 segments
  // with its triangles as written, each triangle's corners rotated, or the triangles shuffled.
  // In this order the same surface gives the same graph in whatever order its file lists it
  // (vertices at the same position, which a closed manifold lumen does not have, would keep their
  // file order).
  void canonicalise() {
    mesh_.collect_garbage();
    std::vector<VertexIndex> order(mesh_.vertices().begin(), mesh_.vertices().end());
    std::stable_sort(order.begin(), order.end(), [&](VertexIndex a, VertexIndex b) {
      return CGAL::compare_xyz(mesh_.point(a), mesh_.point(b)) == CGAL::SMALLER;
    });
    std::vector<std::uint32_t> rank(mesh_.number_of_vertices());
    for (std::size_t i = 0; i < order.size(); ++i) rank[order[i].idx()] = static_cast<std::uint32_t>(i);
    std::vector<std::array<std::uint32_t, 3>> triangles;
    triangles.reserve(mesh_.number_of_faces());
    for (Mesh::Face_index f : mesh_.faces()) {
      std::array<std::uint32_t, 3> t{};
      std::size_t k = 0;
      for (VertexIndex v : CGAL::vertices_around_face(mesh_.halfedge(f), mesh_)) t[k++] = rank[v.idx()];
      std::rotate(t.begin(), std::min_element(t.begin(), t.end()), t.end());
      triangles.push_back(t);
    }
    std::sort(triangles.begin(), triangles.end());
    Mesh sorted;
    for (VertexIndex v : order) sorted.add_vertex(mesh_.point(v));
    for (const std::array<std::uint32_t, 3>& t : triangles) {
      sorted.add_face(VertexIndex(t[0]), VertexIndex(t[1]), VertexIndex(t[2]));
    }
    mesh_ = std::move(sorted);
  }

  // The skeleton's nodes (degree != 2) and the chains between them become branches; a point's
  // radius is its distance to the surface.
  template <typename Lap>
  bool skeletonise(Lap& lap) {
    Skeleton skeleton;
    Skeletonization mcs(mesh_);
    // CGAL's default shortest edge is 0.2 % of the bounding box's diagonal (0.9 mm for a head and
    // neck tree): the flow collapses branches thinner than a few of those into their parent. The
    // input's own median edge keeps them (the mesher resolves every vessel it was given).
    mcs.set_min_edge_length(std::min(mcs.min_edge_length(), median_edge_mm()));
    contract_until_convergence(mcs);
    mcs.convert_to_skeleton(skeleton);
    out_.stats.seconds.flow = lap();
    out_.stats.skeleton_points = boost::num_vertices(skeleton);
    if (boost::num_edges(skeleton) == 0) return refuse("no centreline: the skeleton of the surface is a single point");
    Tree tree(faces(mesh_).first, faces(mesh_).second, mesh_);
    tree.accelerate_distance_queries();
    const auto is_node = [&](SkeletonVertex v) { return boost::degree(v, skeleton) != 2; };
    // A branch's ends keep this radius; its inner points get theirs from centre() below.
    const auto radius = [&](SkeletonVertex v) { return std::sqrt(tree.squared_distance(skeleton[v].point)); };
    std::map<std::pair<SkeletonVertex, SkeletonVertex>, bool> walked;  // directed first edges
    const auto walk = [&](SkeletonVertex start, SkeletonVertex next) {
      Branch branch;
      branch.from = start;
      branch.line.where = "skeleton branch " + std::to_string(out_.branches.size());
      branch.line.points.push_back({to_glm(skeleton[start].point), radius(start)});
      SkeletonVertex previous = start;
      SkeletonVertex at = next;
      while (true) {
        const bool end = is_node(at) || at == start;
        branch.line.points.push_back({to_glm(skeleton[at].point), end ? radius(at) : 0.0});
        if (end) break;
        SkeletonVertex following = previous;
        for (auto e : boost::make_iterator_range(boost::out_edges(at, skeleton))) {
          const SkeletonVertex w = boost::target(e, skeleton);
          if (w != previous) following = w;
        }
        previous = at;
        at = following;
      }
      walked[{at, previous}] = true;  // the same chain walked backwards
      branch.to = at;
      out_.branches.push_back(std::move(branch));
    };
    bool any_node = false;
    for (SkeletonVertex v : boost::make_iterator_range(boost::vertices(skeleton))) {
      if (!is_node(v)) continue;
      any_node = true;
      for (auto e : boost::make_iterator_range(boost::out_edges(v, skeleton))) {
        const SkeletonVertex w = boost::target(e, skeleton);
        if (walked.count({v, w}) == 0) {
          walked[{v, w}] = true;
          walk(v, w);
        }
      }
    }
    if (!any_node) {  // a single loop: start anywhere
      const SkeletonVertex v = *boost::vertices(skeleton).first;
      walk(v, boost::target(*boost::out_edges(v, skeleton).first, skeleton));
    }
    for (Branch& branch : out_.branches) centre(branch.line.points, tree);
    return true;
  }

  // CGAL's contract_until_convergence, with the meso-skeleton's halfedges numbered in list order
  // before each collapse pass (the std::less above orders the pass's edges by those numbers).
  void contract_until_convergence(Skeletonization& mcs) const {
    const double original_area = PMP::area(mesh_);
    auto& meso = const_cast<skeleton_order::Meso&>(mcs.meso_skeleton());  // the flow's own, not const
    double last_area = 0.0;
    for (std::size_t iteration = 0; iteration < mcs.max_iterations(); ++iteration) {
      mcs.contract_geometry();
      std::size_t id = 0;
      for (auto h = meso.halfedges_begin(); h != meso.halfedges_end(); ++h) h->id() = id++;
      mcs.collapse_edges();
      mcs.split_faces();
      mcs.detect_degeneracies();
      const double area = PMP::area(meso);
      if (std::abs(last_area - area) / original_area < mcs.area_variation_factor()) break;
      last_area = area;
    }
  }

  // The flow leaves a point off the axis by up to a tenth of the radius where the tube bends.
  // Each inner point climbs the distance to the surface within its cross-section (the plane
  // normal to the branch there) until it is on the medial axis, moving at most half its first
  // distance; its radius is then its distance to the surface. Nodes stay where the flow put them.
  // One closest-point query per step, started from the last closest point (the tree's search
  // then prunes at once: the step moves the point by a fraction of its radius).
  static void centre(std::vector<vessel::CenterlinePoint>& points, const Tree& tree) {
    const std::vector<vessel::CenterlinePoint> before = points;
    for (std::size_t i = 1; i + 1 < points.size(); ++i) {
      const glm::dvec3 tangent = glm::normalize(before[i + 1].pos_mm - before[i - 1].pos_mm);
      const glm::dvec3 start = before[i].pos_mm;
      Point p(start.x, start.y, start.z);
      Point c = tree.closest_point(p);
      double d = std::sqrt(CGAL::squared_distance(p, c));
      const double reach = 0.5 * d;
      double step = 0.25 * d;
      for (int k = 0; k < 24 && step > 1e-4 * d; ++k) {
        glm::dvec3 away = to_glm(p) - to_glm(c);
        away -= glm::dot(away, tangent) * tangent;
        if (glm::length(away) <= 0.0) break;
        const glm::dvec3 q = to_glm(p) + step * glm::normalize(away);
        if (glm::length(q - start) > reach) break;
        const Point qp(q.x, q.y, q.z);
        const Point cq = tree.closest_point(qp, c);
        const double dq = std::sqrt(CGAL::squared_distance(qp, cq));
        if (dq > d) {
          p = qp;
          c = cq;
          d = dq;
        } else {
          step *= 0.5;
        }
      }
      points[i] = {to_glm(p), d};
    }
    if (!points.empty()) {
      points.front().radius_mm = before.front().radius_mm;
      points.back().radius_mm = before.back().radius_mm;
    }
  }

  [[nodiscard]] double median_edge_mm() const {
    std::vector<double> lengths;
    lengths.reserve(mesh_.number_of_edges());
    for (Mesh::Edge_index e : mesh_.edges()) {
      lengths.push_back(std::sqrt(CGAL::squared_distance(mesh_.point(mesh_.vertex(e, 0)), mesh_.point(mesh_.vertex(e, 1)))));
    }
    if (lengths.empty()) return 0.0;
    std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
    return lengths[lengths.size() / 2];
  }

  void keep_lumen() {
    vessel::SurfaceMesh& lumen = out_.lumen;
    std::vector<std::uint32_t> index(mesh_.number_of_vertices());  // the mesh has no garbage (canonicalise)
    for (VertexIndex v : mesh_.vertices()) {
      index[v.idx()] = static_cast<std::uint32_t>(lumen.positions_mm.size());
      lumen.positions_mm.push_back(glm::vec3(to_glm(mesh_.point(v))));
    }
    std::vector<glm::dvec3> normals(lumen.positions_mm.size(), glm::dvec3(0.0));
    for (Mesh::Face_index f : mesh_.faces()) {
      std::uint32_t t[3];
      std::size_t k = 0;
      for (VertexIndex v : CGAL::vertices_around_face(mesh_.halfedge(f), mesh_)) t[k++] = index[v.idx()];
      const glm::dvec3 n = glm::cross(glm::dvec3(lumen.positions_mm[t[1]]) - glm::dvec3(lumen.positions_mm[t[0]]),
                                      glm::dvec3(lumen.positions_mm[t[2]]) - glm::dvec3(lumen.positions_mm[t[0]]));
      for (std::uint32_t i : t) {
        lumen.triangles.push_back(i);
        normals[i] += n;  // area-weighted
      }
      lumen.triangle_regions.push_back({vessel::RegionKind::kSegment, 0});
    }
    lumen.normals.reserve(normals.size());
    for (const glm::dvec3& n : normals) lumen.normals.push_back(glm::vec3(glm::length(n) > 0.0 ? glm::normalize(n) : n));
  }

  std::string file_;
  SurfaceOptions options_;
  Mesh mesh_;
  SurfaceImport out_;
};

}  // namespace

PolygonSoup read_polygon_soup_file(const std::string& path, std::vector<ImportError>& errors) {
  std::vector<Point> points;
  std::vector<std::vector<std::size_t>> polygons;
  PolygonSoup soup;
  bool ok = false;
  try {
    ok = CGAL::IO::read_polygon_soup(path, points, polygons, CGAL::parameters::verbose(false));
  } catch (const std::exception& e) {
    errors.push_back({path, 0, 0, std::string("not a surface: ") + e.what()});
    return soup;
  }
  if (!ok) {
    errors.push_back({path, 0, 0, "not a surface: CGAL could not read it as STL, OBJ, PLY or OFF"});
    return soup;
  }
  soup.points.reserve(points.size());
  for (const Point& p : points) soup.points.push_back(to_glm(p));
  soup.polygons = std::move(polygons);
  return soup;
}

SurfaceImport import_surface_soup(PolygonSoup soup, std::string_view file, const SurfaceOptions& options) {
  try {
    return SurfaceImporter(file, options).run(std::move(soup));
  } catch (const std::exception& e) {  // CGAL's preconditions on a surface no check above caught
    std::string what = e.what();  // CGAL's messages run over several lines
    std::replace(what.begin(), what.end(), '\n', ' ');
    SurfaceImport out;
    out.errors.push_back({std::string(file), 0, 0, "the surface could not be processed: " + what});
    return out;
  }
}

}  // namespace cathbox::vessel_import
