// Surface → repaired closed lumen → mean curvature flow skeleton → branches with radii: the run,
// the flow and the branches (the repair and checks: surface_repair.cpp; the class:
// surface_importer.hpp). With surface_repair.cpp and flow_specialisations.{hpp,cpp}, the only
// files that include CGAL (surface_import.hpp says what each step does and why).
#include <algorithm>
#include <cmath>
#include <ctime>
#include <map>

#include "surface_importer.hpp"

#include <CGAL/IO/polygon_soup_io.h>
#include <CGAL/Polygon_mesh_processing/measure.h>

#include "flow_decimation.hpp"

namespace cathbox::vessel_import {
namespace surface_steps {

template <typename Lap>
bool SurfaceImporter::skeletonise(Lap& lap) {
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

SurfaceImport SurfaceImporter::run(PolygonSoup soup) {
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

[[nodiscard]] Mesh SurfaceImporter::flow_copy() const {
  Mesh copy = mesh_;
  if (copy.number_of_faces() > 2 * kFlowFaces) collapse_shortest_edges(copy, kFlowFaces);
  return copy;
}

void SurfaceImporter::contract_until_convergence(Skeletonization& mcs, const Mesh& flow_mesh) {
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

void SurfaceImporter::centre(std::vector<vessel::CenterlinePoint>& points, const Tree& tree) {
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

[[nodiscard]] double SurfaceImporter::median_edge_mm(const Mesh& mesh) {
  std::vector<double> lengths;
  lengths.reserve(mesh.number_of_edges());
  for (Mesh::Edge_index e : mesh.edges()) {
    lengths.push_back(std::sqrt(CGAL::squared_distance(mesh.point(mesh.vertex(e, 0)), mesh.point(mesh.vertex(e, 1)))));
  }
  if (lengths.empty()) return 0.0;
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  return lengths[lengths.size() / 2];
}

void SurfaceImporter::keep_lumen() {
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

}  // namespace surface_steps

using surface_steps::Point;
using surface_steps::SurfaceImporter;
using surface_steps::to_glm;

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
