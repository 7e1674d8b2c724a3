#include "vessel/subdivision.hpp"

#include <array>
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

constexpr double kPi = 3.14159265358979323846;

// Primvar for OpenSubdiv's refiner (the interface it expects: Clear and AddWithWeight).
// Single precision: positions in mm up to a few hundred mm keep ~1e-5 mm, and half the memory
// traffic makes refinement noticeably faster.
struct Point {
  glm::vec3 p{0.0f};
  void Clear(void* = nullptr) { p = glm::vec3(0.0f); }
  void AddWithWeight(const Point& src, float weight) { p += weight * src.p; }
};

void emit_triangle(SurfaceMesh& out, FaceRegion region, int a, int b, int c) {
  out.triangles.insert(out.triangles.end(),
                       {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c)});
  out.triangle_regions.push_back(region);
}

// A quad as two triangles, split along its shorter diagonal.
void emit_quad(SurfaceMesh& out, FaceRegion region, const int* v) {
  const auto& p = out.positions_mm;
  const float d02 = glm::length(p[static_cast<std::size_t>(v[0])] - p[static_cast<std::size_t>(v[2])]);
  const float d13 = glm::length(p[static_cast<std::size_t>(v[1])] - p[static_cast<std::size_t>(v[3])]);
  if (d02 <= d13) {
    emit_triangle(out, region, v[0], v[1], v[2]);
    emit_triangle(out, region, v[0], v[2], v[3]);
  } else {
    emit_triangle(out, region, v[1], v[2], v[3]);
    emit_triangle(out, region, v[1], v[3], v[0]);
  }
}

// Quad f of an all-quad mesh as triangles 2f and 2f+1 (arrays already sized).
void split_quad(SurfaceMesh& out, std::size_t f, FaceRegion region, const int* v) {
  const auto& p = out.positions_mm;
  const float d02 = glm::length(p[static_cast<std::size_t>(v[0])] - p[static_cast<std::size_t>(v[2])]);
  const float d13 = glm::length(p[static_cast<std::size_t>(v[1])] - p[static_cast<std::size_t>(v[3])]);
  const int s = d02 <= d13 ? 0 : 1;  // first corner of the diagonal
  std::uint32_t* t = out.triangles.data() + 6 * f;
  t[0] = static_cast<std::uint32_t>(v[s]);
  t[1] = static_cast<std::uint32_t>(v[s + 1]);
  t[2] = static_cast<std::uint32_t>(v[s + 2]);
  t[3] = static_cast<std::uint32_t>(v[s]);
  t[4] = static_cast<std::uint32_t>(v[s + 2]);
  t[5] = static_cast<std::uint32_t>(v[(s + 3) % 4]);
  out.triangle_regions[2 * f] = region;
  out.triangle_regions[2 * f + 1] = region;
}

// Unit normal from a (possibly unoriented) direction, turned to the side of `outward`; falls back
// to `outward` when the direction is degenerate.
[[nodiscard]] glm::vec3 oriented_normal(const glm::dvec3& n, const glm::dvec3& outward) {
  glm::dvec3 out = n;
  double len = glm::length(out);
  if (!(len > 1e-12 * std::max(1.0, glm::length(outward))) || !std::isfinite(len)) {
    out = outward;
    len = glm::length(out);
  } else if (glm::dot(out, outward) < 0.0) {
    out = -out;
  }
  return len > 0.0 ? glm::vec3(out / len) : glm::vec3(0.0f, 0.0f, 1.0f);
}

// Catmull-Clark limit positions and normals of the vertices of an all-quad level:
//   interior vertex of valence n, edge neighbours e_i, face-diagonal vertices f_i (between e_i
//   and e_i+1):  P = (n^2 v + 4 sum e_i + sum f_i) / (n (n + 5)),
//   tangents t1/t2 = sum A_n c_i e_i + (c_i + c_i+1) f_i with c_i = cos(2 pi i / n) (resp. sin),
//   A_n = 1 + cos(2 pi / n) + cos(pi / n) sqrt(2 (9 + cos(2 pi / n)))  (Halstead et al. 1993);
//   boundary vertex (crease rule): P = (e_first + 4 v + e_last) / 6.
void limit_by_masks(const std::vector<int>& quads, const Point* src, std::size_t nverts, SurfaceMesh& out) {
  std::vector<std::uint32_t> offset(nverts + 1, 0);
  for (int v : quads) ++offset[static_cast<std::size_t>(v) + 1];
  for (std::size_t i = 0; i < nverts; ++i) offset[i + 1] += offset[i];
  std::vector<std::uint32_t> corners(quads.size());
  {
    std::vector<std::uint32_t> fill(offset.begin(), offset.end() - 1);
    for (std::size_t c = 0; c < quads.size(); ++c) corners[fill[static_cast<std::size_t>(quads[c])]++] = static_cast<std::uint32_t>(c);
  }
  const auto next_of = [&](std::uint32_t c) { return quads[(c & ~3u) | ((c + 1) & 3u)]; };
  const auto opp_of = [&](std::uint32_t c) { return quads[(c & ~3u) | ((c + 2) & 3u)]; };
  const auto prev_of = [&](std::uint32_t c) { return quads[(c & ~3u) | ((c + 3) & 3u)]; };

  std::vector<std::uint32_t> ring;
  std::vector<double> cos_table, sin_table;
  int table_n = 0;
  double a_n = 0.0;
  out.positions_mm.resize(nverts);
  out.normals.resize(nverts);
  for (std::size_t v = 0; v < nverts; ++v) {
    const std::uint32_t* c = corners.data() + offset[v];
    const std::size_t n = offset[v + 1] - offset[v];
    const glm::dvec3 pv(src[v].p);
    if (n == 0) {
      out.positions_mm[v] = glm::vec3(pv);
      out.normals[v] = glm::vec3(0.0f, 0.0f, 1.0f);
      continue;
    }
    // Order the corners around v: the successor of corner a is the corner whose `next` is a's `prev`.
    ring.assign(c, c + n);
    std::size_t start = 0;
    for (std::size_t i = 0; i < n; ++i) {
      bool has_predecessor = false;
      for (std::size_t j = 0; j < n && !has_predecessor; ++j) has_predecessor = prev_of(ring[j]) == next_of(ring[i]);
      if (!has_predecessor) {
        start = i;
        break;
      }
    }
    std::swap(ring[0], ring[start]);
    bool closed = true;
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const int want = prev_of(ring[i]);
      std::size_t j = i + 1;
      while (j < n && next_of(ring[j]) != want) ++j;
      if (j == n) {
        closed = false;  // broken fan (never for our meshes): keep the order found
        break;
      }
      std::swap(ring[i + 1], ring[j]);
    }
    closed = closed && prev_of(ring[n - 1]) == next_of(ring[0]);
    // Outward reference: the corner faces' normals (counter-clockwise faces); one is enough to
    // orient the tangent cross product of an interior vertex.
    glm::dvec3 face_normal(0.0);
    for (std::size_t i = 0; i < (closed ? 1 : n); ++i) {
      const glm::dvec3 a = glm::dvec3(src[next_of(ring[i])].p) - pv;
      const glm::dvec3 b = glm::dvec3(src[prev_of(ring[i])].p) - pv;
      face_normal += glm::cross(a, b);
    }
    if (!closed) {
      const glm::dvec3 first(src[next_of(ring[0])].p);
      const glm::dvec3 last(src[prev_of(ring[n - 1])].p);
      out.positions_mm[v] = glm::vec3((first + 4.0 * pv + last) / 6.0);
      out.normals[v] = oriented_normal(face_normal, face_normal);
      continue;
    }
    const double dn = static_cast<double>(n);
    if (static_cast<int>(n) != table_n) {
      table_n = static_cast<int>(n);
      cos_table.resize(n + 1);
      sin_table.resize(n + 1);
      for (std::size_t i = 0; i <= n; ++i) {
        cos_table[i] = std::cos(2.0 * kPi * static_cast<double>(i) / dn);
        sin_table[i] = std::sin(2.0 * kPi * static_cast<double>(i) / dn);
      }
      a_n = 1.0 + cos_table[1] + std::cos(kPi / dn) * std::sqrt(2.0 * (9.0 + cos_table[1]));
    }
    glm::dvec3 sum_e(0.0), sum_f(0.0), t1(0.0), t2(0.0);
    for (std::size_t i = 0; i < n; ++i) {
      const glm::dvec3 e(src[next_of(ring[i])].p);
      const glm::dvec3 f(src[opp_of(ring[i])].p);
      sum_e += e;
      sum_f += f;
      t1 += a_n * cos_table[i] * e + (cos_table[i] + cos_table[i + 1]) * f;
      t2 += a_n * sin_table[i] * e + (sin_table[i] + sin_table[i + 1]) * f;
    }
    out.positions_mm[v] = glm::vec3((dn * dn * pv + 4.0 * sum_e + sum_f) / (dn * (dn + 5.0)));
    out.normals[v] = oriented_normal(glm::cross(t1, t2), face_normal);
  }
}

void limit_by_opensubdiv(const Far::PrimvarRefinerReal<float>& primvar, const Point* src, const std::vector<int>& quads,
                         std::size_t nverts, SurfaceMesh& out) {
  std::vector<Point> limit(nverts), du(nverts), dv(nverts);
  primvar.Limit(src, limit, du, dv);
  std::vector<glm::dvec3> face_normal(nverts, glm::dvec3(0.0));
  for (std::size_t f = 0; f + 3 < quads.size(); f += 4) {
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

SurfaceMeshResult control_mesh_as_surface(const ControlMesh& control) {
  SurfaceMeshResult result;
  SurfaceMesh& out = result.mesh;
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
  return result;
}

}  // namespace

SurfaceMeshResult subdivide(const ControlMesh& control, int level, LimitMethod method) {
  SurfaceMeshResult result;
  if (level < 0 || level > 6) {
    result.error = "subdivision level must be between 0 and 6, got " + std::to_string(level);
    return result;
  }
  if (control.face_count() == 0) {
    result.error = "the control mesh has no faces";
    return result;
  }
  if (level == 0) return control_mesh_as_surface(control);

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
  // PrimvarRefiner::Limit needs the last level's neighbourhoods; the masks build their own.
  uniform.fullTopologyInLastLevel = method == LimitMethod::kOpenSubdiv;
  refiner->RefineUniform(uniform);

  std::vector<Point> verts(static_cast<std::size_t>(refiner->GetNumVerticesTotal()));
  for (std::size_t i = 0; i < control.vertex_count(); ++i) verts[i].p = glm::vec3(control.positions_mm[i]);
  Far::PrimvarRefinerReal<float> primvar(*refiner);
  Point* src = verts.data();
  for (int l = 1; l <= level; ++l) {
    Point* dst = src + refiner->GetLevel(l - 1).GetNumVertices();
    primvar.Interpolate(l, src, dst);
    src = dst;
  }
  const Far::TopologyLevel& last = refiner->GetLevel(level);
  const auto nverts = static_cast<std::size_t>(last.GetNumVertices());
  const auto nfaces = static_cast<std::size_t>(last.GetNumFaces());
  std::vector<int> quads(4 * nfaces);
  for (std::size_t f = 0; f < nfaces; ++f) {
    const auto fv = last.GetFaceVertices(static_cast<int>(f));
    if (fv.size() != 4) {
      result.error = "refined face is not a quad";
      return result;
    }
    for (int k = 0; k < 4; ++k) quads[4 * f + static_cast<std::size_t>(k)] = fv[k];
  }
  SurfaceMesh& out = result.mesh;
  if (method == LimitMethod::kOpenSubdiv) limit_by_opensubdiv(primvar, src, quads, nverts, out);
  else limit_by_masks(quads, src, nverts, out);

  // Triangles, each with the region of the control face it descends from.
  out.triangles.resize(6 * nfaces);
  out.triangle_regions.resize(2 * nfaces);
  for (std::size_t f = 0; f < nfaces; ++f) {
    int face = static_cast<int>(f);
    for (int l = level; l >= 1; --l) face = refiner->GetLevel(l).GetFaceParentFace(face);
    split_quad(out, f, control.face_regions[static_cast<std::size_t>(face)], quads.data() + 4 * f);
  }
  return result;
}

}  // namespace cathbox::vessel
