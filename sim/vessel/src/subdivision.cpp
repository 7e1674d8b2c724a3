#include "vessel/subdivision.hpp"

#include <cmath>
#include <memory>

#include <glm/geometric.hpp>
#include <opensubdiv/far/primvarRefiner.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

namespace cathbox::vessel {
namespace {

namespace Far = OpenSubdiv::Far;
namespace Sdc = OpenSubdiv::Sdc;

// Primvar for OpenSubdiv's refiner (the interface it expects: Clear and AddWithWeight).
struct Point {
  glm::dvec3 p{0.0};
  void Clear(void* = nullptr) { p = glm::dvec3(0.0); }
  void AddWithWeight(const Point& src, double weight) { p += weight * src.p; }
};

// Splits each polygon into triangles (quads along the shorter diagonal, others as a fan).
void triangulate(const std::vector<glm::dvec3>& pos, const int* sizes, const int* verts, std::size_t faces,
                 const std::vector<FaceRegion>& regions, SurfaceMesh& out) {
  std::size_t offset = 0;
  for (std::size_t f = 0; f < faces; ++f) {
    const int n = sizes[f];
    const int* v = verts + offset;
    offset += static_cast<std::size_t>(n);
    const auto emit = [&](int a, int b, int c) {
      out.triangles.insert(out.triangles.end(), {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b),
                                                 static_cast<std::uint32_t>(c)});
      out.triangle_regions.push_back(regions[f]);
    };
    if (n == 4) {
      const double d02 = glm::length(pos[static_cast<std::size_t>(v[0])] - pos[static_cast<std::size_t>(v[2])]);
      const double d13 = glm::length(pos[static_cast<std::size_t>(v[1])] - pos[static_cast<std::size_t>(v[3])]);
      if (d02 <= d13) {
        emit(v[0], v[1], v[2]);
        emit(v[0], v[2], v[3]);
      } else {
        emit(v[1], v[2], v[3]);
        emit(v[1], v[3], v[0]);
      }
      continue;
    }
    for (int k = 1; k + 1 < n; ++k) emit(v[0], v[k], v[k + 1]);
  }
}

// Area-weighted face normals summed at the vertices.
[[nodiscard]] std::vector<glm::dvec3> face_normals_at_vertices(const std::vector<glm::dvec3>& pos,
                                                               const std::vector<std::uint32_t>& tris) {
  std::vector<glm::dvec3> acc(pos.size(), glm::dvec3(0.0));
  for (std::size_t t = 0; t + 2 < tris.size(); t += 3) {
    const glm::dvec3 n = glm::cross(pos[tris[t + 1]] - pos[tris[t]], pos[tris[t + 2]] - pos[tris[t]]);
    for (int k = 0; k < 3; ++k) acc[tris[t + static_cast<std::size_t>(k)]] += n;
  }
  return acc;
}

void finish(const std::vector<glm::dvec3>& pos, const std::vector<glm::dvec3>* limit_normals, SurfaceMesh& out) {
  const std::vector<glm::dvec3> face_acc = face_normals_at_vertices(pos, out.triangles);
  out.positions_mm.resize(pos.size());
  out.normals.resize(pos.size());
  for (std::size_t i = 0; i < pos.size(); ++i) {
    out.positions_mm[i] = glm::vec3(pos[i]);
    glm::dvec3 n = limit_normals ? (*limit_normals)[i] : face_acc[i];
    const double len = glm::length(n);
    if (!(len > 1e-12) || !std::isfinite(len)) {
      n = face_acc[i];
    } else if (glm::dot(n, face_acc[i]) < 0.0) {
      n = -n;  // the limit tangents' handedness does not fix the side; the faces do
    }
    const double n_len = glm::length(n);
    out.normals[i] = n_len > 0.0 ? glm::vec3(n / n_len) : glm::vec3(0.0f, 0.0f, 1.0f);
  }
}

}  // namespace

SurfaceMeshResult subdivide(const ControlMesh& control, int level) {
  SurfaceMeshResult result;
  if (level < 0 || level > 6) {
    result.error = "subdivision level must be between 0 and 6, got " + std::to_string(level);
    return result;
  }
  if (control.face_count() == 0) {
    result.error = "the control mesh has no faces";
    return result;
  }
  if (level == 0) {
    triangulate(control.positions_mm, control.face_sizes.data(), control.face_vertices.data(), control.face_count(),
                control.face_regions, result.mesh);
    finish(control.positions_mm, nullptr, result.mesh);
    return result;
  }

  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(control.vertex_count());
  desc.numFaces = static_cast<int>(control.face_count());
  desc.numVertsPerFace = control.face_sizes.data();
  desc.vertIndicesPerFace = control.face_vertices.data();
  Sdc::Options sdc_options;
  sdc_options.SetVtxBoundaryInterpolation(Sdc::Options::VTX_BOUNDARY_EDGE_ONLY);
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  std::unique_ptr<Far::TopologyRefiner> refiner(
      Factory::Create(desc, Factory::Options(Sdc::SCHEME_CATMARK, sdc_options)));
  if (!refiner) {
    result.error = "OpenSubdiv rejected the control mesh topology";
    return result;
  }
  Far::TopologyRefiner::UniformOptions uniform(level);
  uniform.fullTopologyInLastLevel = true;  // the limit masks need the last level's neighbourhoods
  refiner->RefineUniform(uniform);

  std::vector<Point> verts(static_cast<std::size_t>(refiner->GetNumVerticesTotal()));
  for (std::size_t i = 0; i < control.vertex_count(); ++i) verts[i].p = control.positions_mm[i];
  Far::PrimvarRefinerReal<double> primvar(*refiner);
  Point* src = verts.data();
  for (int l = 1; l <= level; ++l) {
    Point* dst = src + refiner->GetLevel(l - 1).GetNumVertices();
    primvar.Interpolate(l, src, dst);
    src = dst;
  }
  const Far::TopologyLevel& last = refiner->GetLevel(level);
  const auto nverts = static_cast<std::size_t>(last.GetNumVertices());
  std::vector<Point> limit(nverts);
  std::vector<Point> du(nverts);
  std::vector<Point> dv(nverts);
  primvar.Limit(src, limit, du, dv);

  // Regions: follow each refined face back to its control face.
  const auto nfaces = static_cast<std::size_t>(last.GetNumFaces());
  std::vector<int> base(nfaces);
  for (std::size_t f = 0; f < nfaces; ++f) {
    int face = static_cast<int>(f);
    for (int l = level; l >= 1; --l) face = refiner->GetLevel(l).GetFaceParentFace(face);
    base[f] = face;
  }
  std::vector<FaceRegion> regions(nfaces);
  std::vector<int> sizes(nfaces);
  std::vector<int> indices;
  indices.reserve(nfaces * 4);
  for (std::size_t f = 0; f < nfaces; ++f) {
    regions[f] = control.face_regions[static_cast<std::size_t>(base[f])];
    const auto fv = last.GetFaceVertices(static_cast<int>(f));
    sizes[f] = fv.size();
    for (int k = 0; k < fv.size(); ++k) indices.push_back(fv[k]);
  }
  std::vector<glm::dvec3> pos(nverts);
  std::vector<glm::dvec3> normals(nverts);
  for (std::size_t i = 0; i < nverts; ++i) {
    pos[i] = limit[i].p;
    normals[i] = glm::cross(du[i].p, dv[i].p);
  }
  result.mesh.triangles.reserve(nfaces * 6);
  result.mesh.triangle_regions.reserve(nfaces * 2);
  triangulate(pos, sizes.data(), indices.data(), nfaces, regions, result.mesh);
  finish(pos, &normals, result.mesh);
  return result;
}

}  // namespace cathbox::vessel
