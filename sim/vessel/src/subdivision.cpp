#include "vessel/subdivision.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <type_traits>

#include <sys/mman.h>
#include <unistd.h>

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
// Trivially constructible, so scratch arrays of it that are fully overwritten are not zeroed first.
struct Point {
  glm::vec3 p;
  void Clear(void* = nullptr) { p = glm::vec3(0.0f); }
  void AddWithWeight(const Point& src, float weight) { p += weight * src.p; }
};
static_assert(std::is_trivially_default_constructible_v<Point>);

// Maps the whole pages inside [data, data + bytes) writable in one call (MADV_POPULATE_WRITE,
// Linux 5.14+) instead of one page fault per 4 KB page as they are first written; the buffers
// here are written in full right after. Advice only: where it is unsupported the pages fault in.
void prefault(const void* data, std::size_t bytes) {
#ifdef MADV_POPULATE_WRITE
  static const auto page = static_cast<std::uintptr_t>(sysconf(_SC_PAGESIZE));
  const auto begin = (reinterpret_cast<std::uintptr_t>(data) + page - 1) & ~(page - 1);
  const auto end = (reinterpret_cast<std::uintptr_t>(data) + bytes) & ~(page - 1);
  if (end > begin) (void)madvise(reinterpret_cast<void*>(begin), end - begin, MADV_POPULATE_WRITE);
#else
  (void)data;
  (void)bytes;
#endif
}

void emit_triangle(SurfaceMesh& out, FaceRegion region, int a, int b, int c) {
  out.triangles.insert(out.triangles.end(),
                       {static_cast<std::uint32_t>(a), static_cast<std::uint32_t>(b), static_cast<std::uint32_t>(c)});
  out.triangle_regions.push_back(region);
}

// The first corner (0 or 1) of the shorter diagonal of quad v: 0 when |p0 - p2| <= |p1 - p3| as
// glm::length gives them. The squared lengths decide without a square root except when the
// second is the smaller: the rounded roots may still be equal then, which is a tie (corner 0).
[[nodiscard]] int shorter_diagonal(const std::vector<glm::vec3>& p, const int* v) {
  const glm::vec3 d02 = p[static_cast<std::size_t>(v[0])] - p[static_cast<std::size_t>(v[2])];
  const glm::vec3 d13 = p[static_cast<std::size_t>(v[1])] - p[static_cast<std::size_t>(v[3])];
  const float a = glm::dot(d02, d02);
  const float b = glm::dot(d13, d13);
  return a <= b || std::sqrt(a) <= std::sqrt(b) ? 0 : 1;
}

// Quad v as two triangles, split along its shorter diagonal, written to t[0..5].
void split_quad(const std::vector<glm::vec3>& p, const int* v, std::uint32_t* t) {
  const int s = shorter_diagonal(p, v);
  t[0] = static_cast<std::uint32_t>(v[s]);
  t[1] = static_cast<std::uint32_t>(v[s + 1]);
  t[2] = static_cast<std::uint32_t>(v[s + 2]);
  t[3] = static_cast<std::uint32_t>(v[s]);
  t[4] = static_cast<std::uint32_t>(v[s + 2]);
  t[5] = static_cast<std::uint32_t>(v[(s + 3) % 4]);
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

// Unit normal from a (possibly unoriented) direction, turned to the side of `outward`; falls back
// to `outward` when the direction is degenerate.
[[nodiscard]] glm::vec3 oriented_normal(const glm::dvec3& n, const glm::dvec3& outward) {
  glm::dvec3 out = n;
  const double len2 = glm::dot(out, out);
  double len = std::sqrt(len2);
  const double outward2 = glm::dot(outward, outward);
  // len > 1e-12 max(1, |outward|), decided without the second square root when clear-cut.
  const bool usable = len2 > 1.000001e-24 * std::max(1.0, outward2) || len > 1e-12 * std::max(1.0, std::sqrt(outward2));
  if (!usable || !std::isfinite(len)) {
    out = outward;
    len = std::sqrt(outward2);
  } else if (glm::dot(out, outward) < 0.0) {
    out = -out;
  }
  return len > 0.0 ? glm::vec3(out / len) : glm::vec3(0.0f, 0.0f, 1.0f);
}

// The index in level L of the child vertex of a level L-1 vertex, face or edge.
//  RefinerChildren: as the refiner recorded it (it refined level L itself).
//  UniformChildren: as uniform refinement numbers them (Vtr::Refinement, vertices not ordered
//  from faces first): the children of the vertices, then of the faces, then of the edges, each
//  in parent order. A test checks that both give the same mesh.
struct RefinerChildren {
  static constexpr bool kInOrder = false;
  const Far::TopologyLevel* parent;
  [[nodiscard]] int vertex(int v) const { return parent->GetVertexChildVertex(v); }
  [[nodiscard]] int face(int f) const { return parent->GetFaceChildVertex(f); }
  [[nodiscard]] int edge(int e) const { return parent->GetEdgeChildVertex(e); }
};
struct UniformChildren {
  static constexpr bool kInOrder = true;
  int num_vertices = 0;
  int num_faces = 0;
  explicit UniformChildren(const Far::TopologyLevel& parent)
      : num_vertices(parent.GetNumVertices()), num_faces(parent.GetNumFaces()) {}
  [[nodiscard]] int vertex(int v) const { return v; }
  [[nodiscard]] int face(int f) const { return num_vertices + f; }
  [[nodiscard]] int edge(int e) const { return num_vertices + num_faces + e; }
  [[nodiscard]] int total(const Far::TopologyLevel& parent) const { return num_vertices + num_faces + parent.GetNumEdges(); }
};

// The last refinement step of a closed, manifold mesh without creases (every vertex and edge of
// level L-1 takes the smooth Catmull-Clark rule), done the way Far::PrimvarRefiner does it:
// the same weights (Sdc::Scheme<SCHEME_CATMARK> smooth masks), added in the same order in single
// precision, so the points equal PrimvarRefiner::Interpolate's bit for bit (a test checks).
//   face child:   sum of the face's vertices times 1/n,
//   edge child:   1/4 of both end points, then 1/4 of both faces' children,
//   vertex child: 1/n^2 of each face's child, then 1/n^2 of each edge's far end, then (n-2)/n v.
void refine_smooth_last_level(const Far::TopologyLevel& parent, const UniformChildren& children, const Point* src,
                              Point* dst) {
  for (int f = 0; f < parent.GetNumFaces(); ++f) {
    const auto fv = parent.GetFaceVertices(f);
    const float weight = 1.0f / static_cast<float>(fv.size());
    Point& p = dst[children.face(f)];
    p.Clear();
    for (int i = 0; i < fv.size(); ++i) p.AddWithWeight(src[fv[i]], weight);
  }
  for (int e = 0; e < parent.GetNumEdges(); ++e) {
    const auto ev = parent.GetEdgeVertices(e);
    const auto ef = parent.GetEdgeFaces(e);
    Point& p = dst[children.edge(e)];
    p.Clear();
    p.AddWithWeight(src[ev[0]], 0.25f);
    p.AddWithWeight(src[ev[1]], 0.25f);
    p.AddWithWeight(dst[children.face(ef[0])], 0.25f);
    p.AddWithWeight(dst[children.face(ef[1])], 0.25f);
  }
  for (int v = 0; v < parent.GetNumVertices(); ++v) {
    const auto vf = parent.GetVertexFaces(v);
    const auto ve = parent.GetVertexEdges(v);
    const int n = vf.size();
    const float v_weight = static_cast<float>(n - 2) / static_cast<float>(n);
    const float fe_weight = 1.0f / static_cast<float>(n * n);
    Point& p = dst[children.vertex(v)];
    p.Clear();
    for (int i = 0; i < n; ++i) p.AddWithWeight(dst[children.face(vf[i])], fe_weight);
    for (int i = 0; i < n; ++i) {
      const auto ev = parent.GetEdgeVertices(ve[i]);
      p.AddWithWeight(src[ev[0] == v ? ev[1] : ev[0]], fe_weight);
    }
    p.AddWithWeight(src[v], v_weight);
  }
}

// True when every vertex of the level takes the smooth rule and every edge has two faces and
// no sharpness: a closed manifold without creases, so every finer level is one too.
[[nodiscard]] bool is_smooth_closed(const Far::TopologyLevel& level) {
  for (int v = 0; v < level.GetNumVertices(); ++v)
    if (level.GetVertexRule(v) != Sdc::Crease::RULE_SMOOTH || level.GetVertexFaces(v).size() != level.GetVertexEdges(v).size()) return false;
  for (int e = 0; e < level.GetNumEdges(); ++e)
    if (level.GetEdgeFaces(e).size() != 2 || level.GetEdgeSharpness(e) != 0.0f) return false;
  return true;
}

// Catmull-Clark limit positions and normals of the vertices of level L (L >= 1), each computed
// from its one-ring in level L (the limit masks), the one-ring read off level L-1's ordered
// topology and the parent-to-child indices instead of building level L's neighbourhoods:
//   interior vertex of valence n, edge neighbours e_i counter-clockwise seen from outside,
//   face-diagonal vertices f_i (between e_i and e_i+1):
//     P = (n^2 v + 4 sum e_i + sum f_i) / (n (n + 5)),
//     tangents t1/t2 = sum A_n c_i e_i + (c_i + c_i+1) f_i with c_i = cos(2 pi i / n) (resp. sin),
//     A_n = 1 + cos(2 pi / n) + cos(pi / n) sqrt(2 (9 + cos(2 pi / n)))  (Halstead et al. 1993);
//   boundary vertex (crease rule), edge neighbours e_0..e_n from one boundary edge to the other:
//     P = (e_0 + 4 v + e_n) / 6, normal from the corner faces.
// Level L-1 must be manifold (the caller checks); its faces and vertex fans are oriented.
template <class Children>
class LimitMasks {
 public:
  // With Children::kInOrder the output vectors are appended to (reserved by the caller),
  // otherwise written by index (sized by the caller).
  LimitMasks(const Far::TopologyLevel& parent, Children children, const Point* src, SurfaceMesh& out)
      : parent_(parent), children_(children), src_(src), out_(out) {}

  // In the uniform numbering's order (vertex children, face children, edge children), so that
  // UniformChildren can append to the output instead of zero-filling it first.
  void run() {
    for (int v = 0; v < parent_.GetNumVertices(); ++v) vertex_child(v);
    for (int f = 0; f < parent_.GetNumFaces(); ++f) face_child(f);
    for (int e = 0; e < parent_.GetNumEdges(); ++e) edge_child(e);
  }

 private:
  static constexpr int kTabulated = 64;  // valences with precomputed trigonometry
  struct Trig {
    std::array<double, kTabulated + 1> cos{}, sin{};
    double a_n = 0.0;
  };
  static void fill_trig(int n, Trig& t) {
    const double dn = static_cast<double>(n);
    for (int i = 0; i <= n; ++i) {
      t.cos[static_cast<std::size_t>(i)] = std::cos(2.0 * kPi * static_cast<double>(i) / dn);
      t.sin[static_cast<std::size_t>(i)] = std::sin(2.0 * kPi * static_cast<double>(i) / dn);
    }
    t.a_n = 1.0 + t.cos[1] + std::cos(kPi / dn) * std::sqrt(2.0 * (9.0 + t.cos[1]));
  }
  static const Trig& trig(int n) {
    static const std::array<Trig, kTabulated + 1> table = [] {
      std::array<Trig, kTabulated + 1> t{};
      for (int k = 1; k <= kTabulated; ++k) fill_trig(k, t[static_cast<std::size_t>(k)]);
      return t;
    }();
    return table[static_cast<std::size_t>(n)];
  }

  [[nodiscard]] glm::dvec3 at(int v) const { return glm::dvec3(src_[v].p); }

  // Interior vertex v of valence n: e[0..n-1], f[0..n-1] as above.
  void closed(int v, const int* e, const int* f, int n) {
    if (n == 4) {
      closed4(v, e, f);
    } else if (n > kTabulated) {
      Trig local;
      fill_trig(n, local);
      closed_with(v, e, f, n, local);
    } else {
      closed_with(v, e, f, n, trig(n));
    }
  }

  // Valence 4 (all but the extraordinary vertices): the masks with c_i = 1, 0, -1, 0 and A_4 = 4.
  void closed4(int v, const int* e, const int* f) {
    const glm::dvec3 pv = at(v);
    const glm::dvec3 e0 = at(e[0]), e1 = at(e[1]), e2 = at(e[2]), e3 = at(e[3]);
    const glm::dvec3 f0 = at(f[0]), f1 = at(f[1]), f2 = at(f[2]), f3 = at(f[3]);
    const glm::vec3 position((16.0 * pv + 4.0 * (e0 + e1 + e2 + e3) + (f0 + f1 + f2 + f3)) / 36.0);
    const glm::dvec3 t1 = 4.0 * (e0 - e2) + (f0 - f1) - (f2 - f3);
    const glm::dvec3 t2 = 4.0 * (e1 - e3) + (f0 + f1) - (f2 + f3);
    put(v, position, oriented_normal(glm::cross(t1, t2), glm::cross(e0 - pv, e1 - pv)));
  }

  void closed_with(int v, const int* e, const int* f, int n, const Trig& t) {
    const glm::dvec3 pv = at(v);
    // Outward reference for the tangent cross product: the first corner face's normal.
    const glm::dvec3 face_normal = glm::cross(at(e[0]) - pv, at(e[n > 1 ? 1 : 0]) - pv);
    const double dn = static_cast<double>(n);
    glm::dvec3 sum_e(0.0), sum_f(0.0), t1(0.0), t2(0.0);
    for (std::size_t i = 0; i < static_cast<std::size_t>(n); ++i) {
      const glm::dvec3 ei = at(e[i]);
      const glm::dvec3 fi = at(f[i]);
      sum_e += ei;
      sum_f += fi;
      t1 += t.a_n * t.cos[i] * ei + (t.cos[i] + t.cos[i + 1]) * fi;
      t2 += t.a_n * t.sin[i] * ei + (t.sin[i] + t.sin[i + 1]) * fi;
    }
    put(v, glm::vec3((dn * dn * pv + 4.0 * sum_e + sum_f) / (dn * (dn + 5.0))), oriented_normal(glm::cross(t1, t2), face_normal));
  }

  // Boundary vertex v with n corner faces: e[0..n] from one boundary neighbour to the other.
  void open(int v, const int* e, int n) {
    const glm::dvec3 pv = at(v);
    glm::dvec3 face_normal(0.0);
    for (int i = 0; i < n; ++i) face_normal += glm::cross(at(e[i]) - pv, at(e[i + 1]) - pv);
    put(v, glm::vec3((at(e[0]) + 4.0 * pv + at(e[n])) / 6.0), oriented_normal(face_normal, face_normal));
  }

  void put(int v, const glm::vec3& position, const glm::vec3& normal) {
    if constexpr (Children::kInOrder) {
      out_.positions_mm.push_back(position);
      out_.normals.push_back(normal);
    } else {
      out_.positions_mm[static_cast<std::size_t>(v)] = position;
      out_.normals[static_cast<std::size_t>(v)] = normal;
    }
  }

  [[nodiscard]] int vc(int v) const { return children_.vertex(v); }
  [[nodiscard]] int ec(int e) const { return children_.edge(e); }
  [[nodiscard]] int fc(int f) const { return children_.face(f); }

  // The child of face F (n vertices v_k, edges from v_k to v_k+1): edge neighbours are the
  // children of F's edges, the diagonals the children of its vertices.
  void face_child(int face) {
    const auto fv = parent_.GetFaceVertices(face);
    const auto fe = parent_.GetFaceEdges(face);
    const int n = fv.size();
    reserve_scratch(static_cast<std::size_t>(n));
    for (int i = 0; i < n; ++i) {
      e_[static_cast<std::size_t>(i)] = ec(fe[i]);
      f_[static_cast<std::size_t>(i)] = vc(fv[i + 1 < n ? i + 1 : 0]);
    }
    closed(fc(face), e_.data(), f_.data(), n);
  }

  // The child of edge E = (a, b) as face F0 runs along it (F0 to its left, F1 to its right).
  void edge_child(int edge) {
    const auto faces = parent_.GetEdgeFaces(edge);
    const auto local = parent_.GetEdgeFaceLocalIndices(edge);
    const int v = ec(edge);
    if (faces.size() == 0) {  // no faces (never in a valid mesh): stays where it is
      put(v, src_[v].p, glm::vec3(0.0f, 0.0f, 1.0f));
      return;
    }
    const auto fv0 = parent_.GetFaceVertices(faces[0]);
    const auto fe0 = parent_.GetFaceEdges(faces[0]);
    const int n0 = fv0.size();
    const int k = local[0];
    const int a = vc(fv0[k]);
    const int k_next = k + 1 < n0 ? k + 1 : 0;  // (no integer division in this per-edge code)
    const int b = vc(fv0[k_next]);
    if (faces.size() == 1) {
      const int e[3] = {b, fc(faces[0]), a};
      open(v, e, 2);
      return;
    }
    const auto fe1 = parent_.GetFaceEdges(faces[1]);
    const int n1 = fe1.size();
    const int j = local[1];
    const int e[4] = {b, fc(faces[0]), a, fc(faces[1])};
    const int f[4] = {ec(fe0[k_next]), ec(fe0[k > 0 ? k - 1 : n0 - 1]), ec(fe1[j + 1 < n1 ? j + 1 : 0]),
                      ec(fe1[j > 0 ? j - 1 : n1 - 1])};
    closed4(v, e, f);
  }

  // The child of vertex V: one corner per face F around V, with V at F's local index k:
  // next = child of F's edge k, diagonal = child of F, prev = child of F's edge k-1.
  void vertex_child(int vertex) {
    const auto faces = parent_.GetVertexFaces(vertex);
    const auto local = parent_.GetVertexFaceLocalIndices(vertex);
    const int v = vc(vertex);
    const int n = faces.size();
    if (n == 0) {
      put(v, src_[v].p, glm::vec3(0.0f, 0.0f, 1.0f));
      return;
    }
    const auto un = static_cast<std::size_t>(n);
    reserve_scratch(un);
    for (int i = 0; i < n; ++i) {
      const auto fe = parent_.GetFaceEdges(faces[i]);
      const int k = local[i];
      e_[static_cast<std::size_t>(i)] = ec(fe[k]);
      f_[static_cast<std::size_t>(i)] = fc(faces[i]);
      prev_[static_cast<std::size_t>(i)] = ec(fe[k > 0 ? k - 1 : fe.size() - 1]);
    }
    // The fan is ordered; turn it counter-clockwise (each corner's prev is the next one's next).
    if (n > 1 && prev_[0] != e_[1]) {
      std::reverse(e_.begin(), e_.begin() + n);
      std::reverse(f_.begin(), f_.begin() + n);
      std::reverse(prev_.begin(), prev_.begin() + n);
    }
    if (prev_[un - 1] == e_[0]) {
      closed(v, e_.data(), f_.data(), n);
    } else {
      e_[un] = prev_[un - 1];
      open(v, e_.data(), n);
    }
  }

  // Scratch for n neighbours (+1 on open fans); only grows, so no allocation per vertex.
  void reserve_scratch(std::size_t n) {
    if (e_.size() <= n) {
      e_.resize(n + 1);
      f_.resize(n + 1);
      prev_.resize(n + 1);
    }
  }

  const Far::TopologyLevel& parent_;
  Children children_;
  const Point* src_;
  SurfaceMesh& out_;
  std::vector<int> e_, f_, prev_;  // scratch, reused
};

// The faces of level L (all quads) as two triangles each, straight from level L-1 (`parent`),
// appended in level L's face order: uniform refinement gives face F of n vertices the children
// n_0 + j, j = 0..n-1 (n_0 the children of the faces before F), child j being the quad (child of
// vertex j, of edge j, of F, of edge j-1), rotated by j places when F is a quad so that vertex j's
// child keeps F's local index j.
void emit_child_quads(const Far::TopologyRefiner& refiner, int parent_level, const UniformChildren& children,
                      const std::vector<FaceRegion>& control_regions, SurfaceMesh& out) {
  const Far::TopologyLevel& parent = refiner.GetLevel(parent_level);
  const auto nfaces = static_cast<std::size_t>(parent.GetNumFaceVertices());
  out.triangles.reserve(6 * nfaces);
  out.triangle_regions.reserve(2 * nfaces);
  prefault(out.triangles.data(), 6 * nfaces * sizeof(std::uint32_t));
  prefault(out.triangle_regions.data(), 2 * nfaces * sizeof(FaceRegion));
  std::vector<std::uint32_t> face_triangles;  // one parent face's 2n triangles, appended at once
  for (int f = 0; f < parent.GetNumFaces(); ++f) {
    int ancestor = f;
    for (int l = parent_level; l >= 1; --l) ancestor = refiner.GetLevel(l).GetFaceParentFace(ancestor);
    const FaceRegion region = control_regions[static_cast<std::size_t>(ancestor)];
    const auto fv = parent.GetFaceVertices(f);
    const auto fe = parent.GetFaceEdges(f);
    const int n = fv.size();
    face_triangles.resize(6 * static_cast<std::size_t>(n));
    const int center = children.face(f);
    int previous_edge = children.edge(fe[n - 1]);
    for (int j = 0; j < n; ++j) {
      const int next_edge = children.edge(fe[j]);
      const int rotation = n == 4 ? j : 0;
      int v[4];
      v[rotation] = children.vertex(fv[j]);
      v[(rotation + 1) & 3] = next_edge;
      v[(rotation + 2) & 3] = center;
      v[(rotation + 3) & 3] = previous_edge;
      previous_edge = next_edge;
      split_quad(out.positions_mm, v, face_triangles.data() + 6 * j);
    }
    out.triangles.insert(out.triangles.end(), face_triangles.begin(), face_triangles.end());
    // Within the reserved capacity: inlined appends (vector's fill insert is an out-of-line call
    // with a general path, 3 % of the command at 3,000 segments).
    for (int k = 0; k < 2 * n; ++k) out.triangle_regions.push_back(region);
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
  LimitMasks<UniformChildren>(parent, children, fine.get(), out).run();
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
    LimitMasks<RefinerChildren>(parent, RefinerChildren{&parent}, src, out).run();
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
