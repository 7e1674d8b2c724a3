#include "vessel/subdivision.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

#include <glm/geometric.hpp>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include "subdivision_internal.hpp"

namespace cathbox::vessel {
namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;
using detail::emit_child_quads;
using detail::is_smooth_closed;
using detail::limit_by_masks;
using detail::oriented_normal;
using detail::Point;
using detail::prefault;
using detail::RefinerChildren;
using detail::refine_smooth_last_level;
using detail::shorter_diagonal;
using detail::split_quad;
using detail::UniformChildren;

void emit_triangle(SurfaceMesh& out, FaceRegion region, int a, int b, int c) {
  out.triangles.insert(out.triangles.end(),
                       {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c)});
  out.triangle_regions.push_back(region);
}

// A quad as two triangles, split along its shorter diagonal.
void emit_quad(SurfaceMesh& out, FaceRegion region, const int* v) {
  if (shorter_diagonal(out.positions_mm, v) == 0) {
    emit_triangle(out, region, v[0], v[1], v[2]);
    emit_triangle(out, region, v[0], v[2], v[3]);
  } else {
    emit_triangle(out, region, v[1], v[2], v[3]);
    emit_triangle(out, region, v[1], v[3], v[0]);
  }
}

[[nodiscard]] bool is_manifold(const Far::TopologyLevel& level) {
  for (int v = 0; v < level.GetNumVertices(); ++v)
    if (level.IsVertexNonManifold(v)) return false;
  for (int e = 0; e < level.GetNumEdges(); ++e)
    if (level.IsEdgeNonManifold(e)) return false;
  return true;
}

void limit_by_opensubdiv(const Far::PrimvarRefinerReal<float>& primvar, const Point* src, const int* quads,
                         std::size_t nfaces, std::size_t nverts, SurfaceMesh& out) {
  std::vector<Point> limit(nverts), du(nverts), dv(nverts);
  primvar.Limit(src, limit, du, dv);
  std::vector<glm::dvec3> face_normal(nverts, glm::dvec3(0.0));
  for (std::size_t f = 0; f < 4 * nfaces; f += 4) {
    for (std::size_t k = 0; k < 4; ++k) {
      const auto v = static_cast<std::size_t>(quads[f + k]);
      face_normal[v] += glm::dvec3(glm::cross(src[quads[f + (k + 1) % 4]].p - src[v].p, src[quads[f + (k + 3) % 4]].p - src[v].p));
    }
  }
  out.positions_mm.resize(nverts);
  out.normals.resize(nverts);
  for (std::size_t i = 0; i < nverts; ++i) {
    out.positions_mm[i] = glm::vec3(limit[i].p);
    out.normals[i] = oriented_normal(glm::dvec3(glm::cross(du[i].p, dv[i].p)), face_normal[i]);
  }
}

SurfaceMesh control_mesh_as_surface(const ControlMesh& control) {
  SurfaceMesh out;
  out.positions_mm.reserve(control.vertex_count());
  for (const glm::dvec3& p : control.positions_mm) out.positions_mm.emplace_back(p);
  std::size_t offset = 0;
  for (std::size_t f = 0; f < control.face_count(); ++f) {
    const int n = control.face_sizes[f];
    const int* v = control.face_vertices.data() + offset;
    offset += static_cast<std::size_t>(n);
    if (n == 4) {
      emit_quad(out, control.face_regions[f], v);
    } else {
      for (int k = 1; k + 1 < n; ++k) emit_triangle(out, control.face_regions[f], v[0], v[k], v[k + 1]);
    }
  }
  std::vector<glm::dvec3> acc(control.vertex_count(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < out.triangles.size(); t += 3) {
    const glm::dvec3 a = control.positions_mm[out.triangles[t]];
    const glm::dvec3 n = glm::cross(control.positions_mm[out.triangles[t + 1]] - a, control.positions_mm[out.triangles[t + 2]] - a);
    for (std::size_t k = 0; k < 3; ++k) acc[out.triangles[t + k]] += n;
  }
  out.normals.resize(control.vertex_count());
  for (std::size_t i = 0; i < acc.size(); ++i) out.normals[i] = oriented_normal(acc[i], acc[i]);
  return out;
}

// A refiner level and its points for a LevelAdjuster.
class LevelView final : public RefinedLevel {
 public:
  LevelView(const Far::TopologyLevel& topology, int level, Point* points)
      : topology_(topology), level_(level), points_(points) {}
  [[nodiscard]] int level() const override { return level_; }
  [[nodiscard]] int face_count() const override { return topology_.GetNumFaces(); }
  [[nodiscard]] int vertex_count() const override { return topology_.GetNumVertices(); }
  [[nodiscard]] std::span<const int> face_vertices(int face) const override {
    const auto fv = topology_.GetFaceVertices(face);
    return {fv.begin(), static_cast<std::size_t>(fv.size())};
  }
  [[nodiscard]] int vertex_face_count(int vertex) const override { return topology_.GetVertexFaces(vertex).size(); }
  [[nodiscard]] bool boundary_vertex(int vertex) const override { return topology_.IsVertexBoundary(vertex); }
  [[nodiscard]] glm::vec3 point(int vertex) const override { return points_[vertex].p; }
  void set_point(int vertex, const glm::vec3& p_mm) override { points_[vertex].p = p_mm; }

 private:
  const Far::TopologyLevel& topology_;
  int level_;
  Point* points_;
};


// subdivide's steps.

// OpenSubdiv's topology of the control mesh (Catmull-Clark, boundaries interpolated edge only);
// null when OpenSubdiv rejects it.
[[nodiscard]] std::unique_ptr<Far::TopologyRefiner> make_refiner(const ControlMesh& control) {
  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(control.vertex_count());
  desc.numFaces = static_cast<int>(control.face_count());
  desc.numVertsPerFace = control.face_sizes.data();
  desc.vertIndicesPerFace = control.face_vertices.data();
  Sdc::Options sdc_options;
  sdc_options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  return std::unique_ptr<Far::TopologyRefiner>(Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc_options)));
}

// The method the control mesh allows: the limit masks read each vertex's neighbourhood off the
// previous level, which needs a manifold mesh (the control mesh builder makes one); anything else
// goes to OpenSubdiv's Limit. The last step by hand only where every vertex and edge takes the
// smooth rule (closed, no creases: the default caps); open ends have OpenSubdiv refine level L too.
[[nodiscard]] LimitMethod usable_method(const Far::TopologyLevel& control_level, LimitMethod method) {
  if (method != LimitMethod::kOpenSubdiv && !is_manifold(control_level)) method = LimitMethod::kOpenSubdiv;
  if (method == LimitMethod::kMasks && !is_smooth_closed(control_level)) method = LimitMethod::kMasksOnRefinedLevel;
  return method;
}

// Refines the topology as far as `method` needs, returning that level:
// kMasks: OpenSubdiv refines to level L-1 in full (the masks read its neighbourhoods), the
// last step is refine_smooth_last_level. kMasksOnRefinedLevel: level L by OpenSubdiv, its
// faces only. kOpenSubdiv: level L in full (PrimvarRefiner::Limit needs its neighbourhoods).
int refine_topology(Far::TopologyRefiner& refiner, LimitMethod method, int level) {
  const int osd_levels = method == LimitMethod::kMasks ? level - 1 : level;
  if (osd_levels > 0) {
    Far::TopologyRefiner::UniformOptions uniform(osd_levels);
    uniform.fullTopologyInLastLevel = method != LimitMethod::kMasksOnRefinedLevel;
    refiner.RefineUniform(uniform);
  }
  return osd_levels;
}

// The points of levels 0..osd_levels one after the other (level 0 copied in, Interpolate writes
// the rest), the level before the last handed to `before_last_step` before the last step.
struct LevelPoints {
  std::unique_ptr<Point[]> all;
  Point* last = nullptr;  // the points of level osd_levels
};
[[nodiscard]] LevelPoints interpolate_levels(const Far::TopologyRefiner& refiner, const Far::PrimvarRefinerReal<float>& primvar,
                                             const ControlMesh& control, int level, int osd_levels,
                                             const LevelAdjuster& before_last_step) {
  const auto nverts_total = static_cast<std::size_t>(refiner.GetNumVerticesTotal());
  LevelPoints points{std::make_unique_for_overwrite<Point[]>(nverts_total)};
  prefault(points.all.get(), nverts_total * sizeof(Point));
  for (std::size_t i = 0; i < control.vertex_count(); ++i) points.all[i].p = glm::vec3(control.positions_mm[i]);
  Point* src = points.all.get();
  const auto adjust = [&](int parent_level, Point* level_points) {
    if (!before_last_step) return;
    LevelView view(refiner.GetLevel(parent_level), parent_level, level_points);
    before_last_step(view);
  };
  for (int l = 1; l <= osd_levels; ++l) {
    if (l == level) adjust(l - 1, src);
    Point* dst = src + refiner.GetLevel(l - 1).GetNumVertices();
    primvar.Interpolate(l, src, dst);
    src = dst;
  }
  if (osd_levels < level) adjust(level - 1, src);
  points.last = src;
  return points;
}

// kMasks: the last step done by hand straight into the limit pass, from level L-1's points.
[[nodiscard]] SurfaceMesh limit_from_level_before_last(const Far::TopologyRefiner& refiner, int level, const Point* src,
                                                       const std::vector<FaceRegion>& control_regions) {
  SurfaceMesh out;
  const Far::TopologyLevel& parent = refiner.GetLevel(level - 1);
  const UniformChildren children(parent);
  const auto nfine = static_cast<std::size_t>(children.total(parent));
  const auto fine = std::make_unique_for_overwrite<Point[]>(nfine);  // every entry is written
  prefault(fine.get(), nfine * sizeof(Point));
  refine_smooth_last_level(parent, children, src, fine.get());
  out.positions_mm.reserve(nfine);
  out.normals.reserve(nfine);
  prefault(out.positions_mm.data(), nfine * sizeof(glm::vec3));
  prefault(out.normals.data(), nfine * sizeof(glm::vec3));
  limit_by_masks(parent, children, fine.get(), out);
  emit_child_quads(refiner, level - 1, children, control_regions, out);
  return out;
}

// kMasksOnRefinedLevel and kOpenSubdiv: the limit of level L as OpenSubdiv refined it, its quads
// as triangles, each with the region of the control face it descends from.
[[nodiscard]] SurfaceMeshResult limit_of_refined_level(const Far::TopologyRefiner& refiner,
                                                       const Far::PrimvarRefinerReal<float>& primvar, int level,
                                                       LimitMethod method, const Point* src,
                                                       const std::vector<FaceRegion>& control_regions) {
  SurfaceMesh out;
  const Far::TopologyLevel& parent = refiner.GetLevel(level - 1);
  const Far::TopologyLevel& last = refiner.GetLevel(level);
  const auto nverts = static_cast<std::size_t>(last.GetNumVertices());
  const auto nfaces = static_cast<std::size_t>(last.GetNumFaces());
  // Catmull-Clark faces after one step are quads, stored one after the other.
  const int* quads = last.GetFaceVertices(0).begin();
  if (last.GetNumFaceVertices() != static_cast<int>(4 * nfaces)) return base::Error{"refined face is not a quad"};
  if (method == LimitMethod::kOpenSubdiv) {
    limit_by_opensubdiv(primvar, src, quads, nfaces, nverts, out);
  } else {
    out.positions_mm.resize(nverts);
    out.normals.resize(nverts);
    limit_by_masks(parent, RefinerChildren{&parent}, src, out);
  }
  out.triangles.resize(6 * nfaces);
  out.triangle_regions.resize(2 * nfaces);
  for (std::size_t f = 0; f < nfaces; ++f) {
    int face = static_cast<int>(f);
    for (int l = level; l >= 1; --l) face = refiner.GetLevel(l).GetFaceParentFace(face);
    split_quad(out.positions_mm, quads + 4 * f, out.triangles.data() + 6 * f);
    out.triangle_regions[2 * f] = out.triangle_regions[2 * f + 1] = control_regions[static_cast<std::size_t>(face)];
  }
  return SurfaceMeshResult(std::move(out));
}

}  // namespace

SurfaceMeshResult subdivide(const ControlMesh& control, int level, LimitMethod method, const LevelAdjuster& before_last_step) {
  if (level < 0 || level > 6) return base::Error{"subdivision level must be between 0 and 6, got " + std::to_string(level)};
  if (control.face_count() == 0) return base::Error{"the control mesh has no faces"};
  if (level == 0) return control_mesh_as_surface(control);
  const std::unique_ptr<Far::TopologyRefiner> refiner = make_refiner(control);
  if (!refiner) return base::Error{"OpenSubdiv rejected the control mesh topology"};
  method = usable_method(refiner->GetLevel(0), method);
  const int osd_levels = refine_topology(*refiner, method, level);
  const Far::PrimvarRefinerReal<float> primvar(*refiner);
  const LevelPoints points = interpolate_levels(*refiner, primvar, control, level, osd_levels, before_last_step);
  if (method == LimitMethod::kMasks) {
    return SurfaceMeshResult(limit_from_level_before_last(*refiner, level, points.last, control.face_regions));
  }
  return limit_of_refined_level(*refiner, primvar, level, method, points.last, control.face_regions);
}

}  // namespace cathbox::vessel