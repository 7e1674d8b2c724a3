// The surface importer's repair and checks: the soup in mm made one oriented triangle mesh, its
// largest component kept, its open ends recorded and capped, the lumen checked (closed, a volume,
// no self-intersections), and put in an order of its geometry's own.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

#include "surface_importer.hpp"

#include <CGAL/Polygon_mesh_processing/border.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>

#include "vessel/point_range.hpp"

namespace cathbox::vessel_import::surface_steps {
namespace {

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

}  // namespace

bool SurfaceImporter::to_mesh(PolygonSoup soup) {
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

bool SurfaceImporter::keep_one_component() {
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

bool SurfaceImporter::cap_open_ends() {
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

bool SurfaceImporter::check_lumen() {
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

void SurfaceImporter::canonicalise() {
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

}  // namespace cathbox::vessel_import::surface_steps
