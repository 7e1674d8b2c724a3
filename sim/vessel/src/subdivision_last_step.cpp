// The last Catmull-Clark step done by hand for subdivide()'s kMasks path: level L's points from
// level L-1's, and level L's faces as triangles, both straight from level L-1's topology.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "subdivision_internal.hpp"

namespace cathbox::vessel::detail {

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
bool is_smooth_closed(const Far::TopologyLevel& level) {
  for (int v = 0; v < level.GetNumVertices(); ++v)
    if (level.GetVertexRule(v) != Sdc::Crease::RULE_SMOOTH || level.GetVertexFaces(v).size() != level.GetVertexEdges(v).size()) return false;
  for (int e = 0; e < level.GetNumEdges(); ++e)
    if (level.GetEdgeFaces(e).size() != 2 || level.GetEdgeSharpness(e) != 0.0f) return false;
  return true;
}

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

}  // namespace cathbox::vessel::detail
