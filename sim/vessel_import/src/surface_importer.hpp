#pragma once
// The surface importer's steps (surface_skeleton.cpp: the flow and the branches; surface_repair.cpp:
// the soup made a closed, checked lumen). Private to vessel_import; with flow_specialisations.hpp
// and flow_decimation.hpp the only headers that include CGAL. flow_specialisations.hpp comes
// first: its explicit specialisations must be declared before anything instantiates the flow.
#include <cstddef>
#include <string>
#include <string_view>
#include <vector>

#include "flow_specialisations.hpp"

#include <CGAL/AABB_face_graph_triangle_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Surface_mesh.h>
#include <glm/geometric.hpp>

#include "vessel_import/surface_import.hpp"

namespace cathbox::vessel_import::surface_steps {

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

[[nodiscard]] inline glm::dvec3 to_glm(const Point& p) { return {p.x(), p.y(), p.z()}; }

class SurfaceImporter {
 public:
  SurfaceImporter(std::string_view file, const SurfaceOptions& options) : file_(file), options_(options) {}

  SurfaceImport run(PolygonSoup soup);

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
  bool to_mesh(PolygonSoup soup);

  bool keep_one_component();

  // Every border cycle is an inlet or outlet the segmentation cut: recorded, then capped.
  bool cap_open_ends();

  bool check_lumen();

  // The lumen in an order of its geometry's own, not the file's: vertices sorted by position,
  // each triangle started at its smallest vertex (its winding kept), triangles sorted. The flow's
  // greedy steps (edge collapses, face splits, degeneracies) visit the mesh in its order and the
  // branches they leave depend on it: the head-and-neck tree's STL gave 29, 31 or 37 segments
  // with its triangles as written, each triangle's corners rotated, or the triangles shuffled.
  // In this order the same surface gives the same graph in whatever order its file lists it
  // (vertices at the same position, which a closed manifold lumen does not have, would keep their
  // file order).
  void canonicalise();

  // The skeleton's nodes (degree != 2) and the chains between them become branches; a point's
  // radius is its distance to the surface.
  template <typename Lap>
  bool skeletonise(Lap& lap);

  // The flow runs on a copy of the lumen decimated to kFlowFaces triangles (shortest edges first,
  // collapsed to their midpoints: flow_decimation.cpp) when it has more than twice as many; the
  // distances to the wall (radii, centring, nodes' radii) are measured on the lumen itself. The
  // 293k-triangle head-and-neck tree: 37 segments / 20 junctions, the generator's own (35 / 19 on
  // the full lumen); flow ~1.5 s of CPU at a load of 14 (sim/vessel_import/README.md, "Speed").
  static constexpr std::size_t kFlowFaces = 25'000;
  [[nodiscard]] Mesh flow_copy() const;

  // CGAL's contract_until_convergence, with the meso-skeleton's halfedges numbered in list order
  // before each collapse pass (the std::less above orders the pass's edges by those numbers).
  static void contract_until_convergence(Skeletonization& mcs, const Mesh& flow_mesh);

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
  static void centre(std::vector<vessel::CenterlinePoint>& points, const Tree& tree);

  [[nodiscard]] static double median_edge_mm(const Mesh& mesh);

  void keep_lumen();

  std::string file_;
  SurfaceOptions options_;
  Mesh mesh_;
  SurfaceImport out_;
};

}  // namespace cathbox::vessel_import::surface_steps
