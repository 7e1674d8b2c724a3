// The flow's Voronoi poles and contraction step: CGAL 5.5's, specialised for speed with the same
// linear system in the same order (flow_specialisations.hpp declares them).
#include "flow_specialisations.hpp"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

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
    // The tree keeps its triangles (CacheDatum) rather than rebuilding each from the halfedges.
    using Cached = CGAL::AABB_face_graph_triangle_primitive<mTriangleMesh, CGAL::Default, CGAL::Tag_true, CGAL::Tag_true>;
    using CachedTree = CGAL::AABB_tree<CGAL::AABB_traits<Traits, Cached>>;
    const Side_of_triangle_mesh<mTriangleMesh, Traits, CGAL::Default, CachedTree> test_inside(m_tmesh);
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

// The angle at each halfedge's opposite corner, for the flow's face splits (an edge is split when
// both its opposite angles are at least alpha_TH, the larger one's corner projected onto it).
// CGAL 5.5 takes an acos at every halfedge on every step (8 % of the import's CPU with the
// traversal); here only where the cosine is within 1e-6 of cos(alpha_TH) or beyond, the only
// angles the splits compare. Below that the stored -1 is, like the true angle, under alpha_TH
// (acos is monotone and its error is an ulp, far inside the margin), so the same edges split.
template <>
void cathbox::vessel_import::skeleton_order::Skeletonization::compute_incident_angle() {
  m_halfedge_angle.assign(2 * num_edges(m_tmesh), 0.0);
  std::size_t idx = 0;
  for (halfedge_descriptor hd : halfedges(m_tmesh)) put(m_hedge_id_pmap, hd, idx++);
  const double near_threshold = std::cos(m_alpha_TH) + 1e-6;
  for (halfedge_descriptor hd : halfedges(m_tmesh)) {
    double& angle = m_halfedge_angle[get(m_hedge_id_pmap, hd)];
    angle = -1.0;
    if (is_border(hd, m_tmesh)) continue;
    const Point& pi = get(m_tmesh_point_pmap, source(hd, m_tmesh));
    const Point& pj = get(m_tmesh_point_pmap, target(hd, m_tmesh));
    const Point& pk = get(m_tmesh_point_pmap, target(next(hd, m_tmesh), m_tmesh));
    const double dis2_ij = CGAL::squared_distance(pi, pj);
    const double dis2_ik = CGAL::squared_distance(pi, pk);
    const double dis2_jk = CGAL::squared_distance(pj, pk);
    const double dis_ik = std::sqrt(dis2_ik);
    const double dis_jk = std::sqrt(dis2_jk);
    // A degenerate triangle is never split (the flow collapses it instead).
    if (std::sqrt(dis2_ij) < m_zero_TH || dis_ik < m_zero_TH || dis_jk < m_zero_TH) continue;
    const double cosine = (dis2_ik + dis2_jk - dis2_ij) / (2.0 * dis_ik * dis_jk);
    if (cosine <= near_threshold) angle = std::acos(cosine);
  }
}
