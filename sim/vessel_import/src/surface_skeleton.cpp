// Surface → repaired closed lumen → mean curvature flow skeleton → branches with radii. With
// flow_specialisations.{hpp,cpp}, the only files that include CGAL (surface_import.hpp says what
// each step does and why).
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

#include "flow_decimation.hpp"
#include "flow_specialisations.hpp"

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
// The triangles are kept in the tree's primitives (CacheDatum): the centring's closest-point
// queries visit many nearly equidistant triangles of the tube around each point, and rebuilding
// each from the mesh's halfedges took a third of their time. The same triangles, the same answers.
using Primitive = CGAL::AABB_face_graph_triangle_primitive<Mesh, CGAL::Default, CGAL::Tag_true, CGAL::Tag_true>;
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
    // polygon_soup_to_polygon_mesh without its precondition, the same check as above run again
    // (this build keeps CGAL's preconditions): 0.45 s on a 294k-triangle soup.
    PMP::internal::PS_to_PM_converter<std::vector<Point>, std::vector<std::vector<std::size_t>>> converter(points, soup.polygons);
    converter(mesh_, get(CGAL::vertex_point, mesh_));
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
    CGAL::Bbox_3 box;
    for (VertexIndex v : mesh_.vertices()) box += mesh_.point(v).bbox();
    out_.stats.extent_mm = std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()});
    // An open sheet (a disc, a cut-open wall) is closed by its cap onto itself: it encloses nothing.
    const double volume = std::abs(PMP::volume(mesh_));
    if (volume <= 1e-6 * std::pow(out_.stats.extent_mm, 3.0)) {
      return refuse("no closed lumen: the surface and the caps of its " + std::to_string(out_.stats.open_ends.size()) +
                    " open ends enclose " + mm(volume) + "3 in a " + mm(out_.stats.extent_mm) +
                    " extent (an open sheet, not a vessel's wall)");
    }
    if (PMP::does_self_intersect(mesh_)) {
      std::vector<std::pair<Mesh::Face_index, Mesh::Face_index>> pairs;
      PMP::self_intersections(mesh_, std::back_inserter(pairs));
      const glm::dvec3 at = to_glm(mesh_.point(mesh_.target(mesh_.halfedge(pairs.front().first))));
      return refuse("self-intersections beyond repair: " + std::to_string(pairs.size()) +
                    " pairs of triangles cross, the first near (" + mm(at.x) + ", " + mm(at.y) + ", " + mm(at.z) + ")");
    }
    if (!PMP::is_outward_oriented(mesh_)) PMP::reverse_face_orientations(mesh_);
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
    const Mesh flow_mesh = flow_copy();
    Skeletonization mcs(flow_mesh);
    // CGAL's default shortest edge is 0.2 % of the bounding box's diagonal (0.9 mm for a head and
    // neck tree): the flow collapses branches thinner than a few of those into their parent. The
    // flow mesh's own median edge keeps them (the mesher resolves every vessel it was given; on
    // the decimated copy, the full lumen's shorter median gave 42 / 22 with extra spurs).
    mcs.set_min_edge_length(std::min(mcs.min_edge_length(), median_edge_mm(flow_mesh)));
    contract_until_convergence(mcs, flow_mesh);
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

  // The flow runs on a copy of the lumen decimated to kFlowFaces triangles (shortest edges first,
  // collapsed to their midpoints: flow_decimation.cpp) when it has more than twice as many; the
  // distances to the wall (radii, centring, nodes' radii) are measured on the lumen itself. The
  // 293k-triangle head-and-neck tree: 37 segments / 20 junctions, the generator's own (35 / 19 on
  // the full lumen); flow ~1.5 s of CPU at a load of 14 (sim/vessel_import/README.md, "Speed").
  static constexpr std::size_t kFlowFaces = 25'000;
  [[nodiscard]] Mesh flow_copy() const {
    Mesh copy = mesh_;
    if (copy.number_of_faces() > 2 * kFlowFaces) collapse_shortest_edges(copy, kFlowFaces);
    return copy;
  }

  // CGAL's contract_until_convergence, with the meso-skeleton's halfedges numbered in list order
  // before each collapse pass (the std::less above orders the pass's edges by those numbers).
  static void contract_until_convergence(Skeletonization& mcs, const Mesh& flow_mesh) {
    const double original_area = PMP::area(flow_mesh);
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

  // The flow leaves a point off the axis by up to a tenth of the radius where the tube bends
  // (and, on the decimated copy, near a junction by up to a quarter of it). Each inner point
  // climbs the distance to the surface within its cross-section (the plane normal to the branch
  // there) until it is on the medial axis, moving at most its first distance (within the empty
  // ball about where the flow put it, so inside the lumen): a step that would go further is halved
  // like one that does not climb (ending the climb there left the fine Y's point 0.094 mm off the
  // axis, 4.3 % small; a reach of half the first distance left the Y's OBJ point beside the carina
  // 0.10 mm off, 6.7 % small). Its radius is then its distance to the surface. Nodes stay where
  // the flow put them.
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
      const double reach = d;  // the empty ball about the start: inside the lumen
      double step = 0.25 * d;
      for (int k = 0; k < 24 && step > 1e-4 * d; ++k) {
        glm::dvec3 away = to_glm(p) - to_glm(c);
        away -= glm::dot(away, tangent) * tangent;
        if (glm::length(away) <= 0.0) break;
        const glm::dvec3 q = to_glm(p) + step * glm::normalize(away);
        if (glm::length(q - start) > reach) {
          step *= 0.5;
          continue;
        }
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

  [[nodiscard]] static double median_edge_mm(const Mesh& mesh) {
    std::vector<double> lengths;
    lengths.reserve(mesh.number_of_edges());
    for (Mesh::Edge_index e : mesh.edges()) {
      lengths.push_back(std::sqrt(CGAL::squared_distance(mesh.point(mesh.vertex(e, 0)), mesh.point(mesh.vertex(e, 1)))));
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
