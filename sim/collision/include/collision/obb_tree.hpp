#pragma once
// An oriented-bounding-box tree over the vessel surface, for the haptic loop and the renderer.
//
// Top levels follow the vessel network (seed thesis 4.2.1): the root groups the vessel's regions
// (segments, junctions, end caps), every region is one subtree, and inside a region the
// triangles are split at the median along the longest box axis so the tree stays balanced and
// tight. The binary tree is then flattened into 4-wide nodes whose four child boxes sit side by
// side in float lanes (one SIMD test per node); leaves hold up to 4 triangles, likewise in lanes.
// Floats only prune; every reported distance is computed in double on the mesh's own vertices,
// so results equal a brute-force search over all triangles.
//
// Queries never allocate and never throw; bad input (NaN, negative radius) gives an empty
// result. The tree is immutable after build and can be shared between threads.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <string>

#include <glm/vec3.hpp>

#include "base/result.hpp"
#include "collision/closest_point.hpp"
#include "collision/contact.hpp"
#include "collision/query_hint.hpp"
#include "collision/ray_hit.hpp"
#include "vessel/surface_mesh.hpp"

namespace cathbox::collision {

namespace detail {
struct TreeData;
struct RegionCache;
}

struct BuildOptions {
  // A coherent query refills its hint with a cut of the tree that covers (needed radius +
  // 2 * margin) around the node, so that the node can move up to `margin` before the next refill.
  double coherence_margin_mm = 0.25;
};

struct TreeStats {
  std::size_t triangles = 0;           // triangles in the tree
  std::size_t degenerate_dropped = 0;  // zero-area triangles left out (they add no surface)
  std::size_t regions = 0;             // distinct FaceRegions (subtrees under the root groups)
  std::size_t wide_nodes = 0;
  std::size_t leaves = 0;
  std::size_t depth = 0;               // wide levels from root to the deepest leaf
  bool closed = false;                 // every edge has exactly one opposite edge
  bool consistently_oriented = false;  // neighbours traverse shared edges in opposite directions
};

// What one build leaves for the next build of a similar mesh: the same vessel with a few
// regions changed (a balloon widened one segment). Per region (FaceRegion) it keeps the
// triangles' corners and the region's subtree; a build given the cache reuses the subtree of
// every region whose triangles are the same floats in the same order (and the same overall
// coordinate scale), so the tree equals a fresh build's while only the changed regions are
// split and fitted again, then refills the cache from itself. One build at a time.
class TreeCache {
 public:
  TreeCache();
  ~TreeCache();
  TreeCache(TreeCache&&) noexcept;
  TreeCache& operator=(TreeCache&&) noexcept;
  // Regions of the last build taken from the cache, and built afresh.
  [[nodiscard]] std::size_t reused_regions() const;
  [[nodiscard]] std::size_t built_regions() const;

 private:
  friend class TreeBuilder;
  std::unique_ptr<detail::RegionCache> data_;
};

class ObbTree;
// The tree, or one line naming the field and index at fault.
using TreeBuild = base::Result<ObbTree>;

class ObbTree {
 public:
  static constexpr double kNoLimit = std::numeric_limits<double>::infinity();

  // Validates the mesh (finite positions, indices in range, one region per triangle) and builds.
  [[nodiscard]] static TreeBuild build(const vessel::SurfaceMesh& mesh,
                                       const BuildOptions& options = {});
  // The same, reusing the unchanged regions of the build `cache` was last given to (if any),
  // and leaving this build's regions in it.
  [[nodiscard]] static TreeBuild build(const vessel::SurfaceMesh& mesh, const BuildOptions& options,
                                       TreeCache& cache);

  [[nodiscard]] const TreeStats& stats() const;
  // A hash of everything the queries read (nodes, leaf blocks, the mesh copy, normals,
  // neighbours; not the tree's id): equal for two trees that answer every query the same.
  [[nodiscard]] std::uint64_t content_hash() const;

  // Nearest wall point within max_distance_mm (inclusive); empty if none or bad input.
  [[nodiscard]] std::optional<ClosestPoint> closest_point(const glm::dvec3& point_mm,
                                                          double max_distance_mm = kNoLimit) const;
  [[nodiscard]] std::optional<ClosestPoint> closest_point(const glm::dvec3& point_mm,
                                                          double max_distance_mm,
                                                          QueryHint& hint) const;

  // Signed distance to the wall (negative inside the lumen); empty on bad input.
  [[nodiscard]] std::optional<double> signed_distance(const glm::dvec3& point_mm) const;
  // True inside the lumen (the closed mesh), false outside; empty on bad input.
  [[nodiscard]] std::optional<bool> contains(const glm::dvec3& point_mm) const;

  // Contacts of a sphere (tool node) with the wall: one per local minimum of the distance from
  // the centre over the wall closer than the radius, deepest first (always including the
  // deepest). Writes at most out.size() contacts and returns how many; 0 on bad input.
  [[nodiscard]] std::size_t sphere_contacts(const glm::dvec3& centre_mm, double radius_mm,
                                            std::span<Contact> out) const;
  [[nodiscard]] std::size_t sphere_contacts(const glm::dvec3& centre_mm, double radius_mm,
                                            std::span<Contact> out, QueryHint& hint) const;
  // The same in one pass with the closest point: `nearest` is the closest wall point (as
  // closest_point gives it) when one lies closer than the radius, else empty. A tool node
  // touching the wall needs both, and every triangle the closest point could be on is among the
  // contact candidates. With out empty (or bad input) nothing is searched: 0 and empty.
  [[nodiscard]] std::size_t sphere_contacts(const glm::dvec3& centre_mm, double radius_mm,
                                            std::span<Contact> out, QueryHint& hint,
                                            std::optional<ClosestPoint>& nearest) const;

  // Contacts of a capsule (segment a-b swept by a sphere of radius_mm, a tool edge), as above
  // with the distance from the segment; Contact::segment_t says where along a-b.
  [[nodiscard]] std::size_t capsule_contacts(const glm::dvec3& a_mm, const glm::dvec3& b_mm,
                                             double radius_mm, std::span<Contact> out) const;
  [[nodiscard]] std::size_t capsule_contacts(const glm::dvec3& a_mm, const glm::dvec3& b_mm,
                                             double radius_mm, std::span<Contact> out,
                                             QueryHint& hint) const;

  // First hit of origin + t * direction for t in [0, max_t]; direction need not be unit.
  [[nodiscard]] std::optional<RayHit> ray_cast(const glm::dvec3& origin_mm,
                                               const glm::dvec3& direction,
                                               double max_t = kNoLimit) const;

 private:
  explicit ObbTree(std::shared_ptr<const detail::TreeData> data) : data_(std::move(data)) {}
  friend class TreeBuilder;
  std::shared_ptr<const detail::TreeData> data_;
};


}  // namespace cathbox::collision
