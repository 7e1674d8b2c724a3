// Catmull-Clark limit positions and normals from each vertex's one-ring (the limit masks), for
// subdivide()'s kMasks and kMasksOnRefinedLevel paths.
#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <vector>

#include <glm/geometric.hpp>

#include "subdivision_internal.hpp"

namespace cathbox::vessel::detail {
namespace {


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
      t.cos[static_cast<std::size_t>(i)] = std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / dn);
      t.sin[static_cast<std::size_t>(i)] = std::sin(2.0 * std::numbers::pi * static_cast<double>(i) / dn);
    }
    t.a_n = 1.0 + t.cos[1] + std::cos(std::numbers::pi / dn) * std::sqrt(2.0 * (9.0 + t.cos[1]));
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

}  // namespace

// Unit normal from a (possibly unoriented) direction, turned to the side of `outward`; falls back
// to `outward` when the direction is degenerate.
glm::vec3 oriented_normal(const glm::dvec3& n, const glm::dvec3& outward) {
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

void limit_by_masks(const Far::TopologyLevel& parent, const UniformChildren& children, const Point* src, SurfaceMesh& out) {
  LimitMasks<UniformChildren>(parent, children, src, out).run();
}

void limit_by_masks(const Far::TopologyLevel& parent, const RefinerChildren& children, const Point* src, SurfaceMesh& out) {
  LimitMasks<RefinerChildren>(parent, children, src, out).run();
}

}  // namespace cathbox::vessel::detail
