#include "tree_builder.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "obb_fit.hpp"
#include "tree_data.hpp"
#include "triangle_block.hpp"

namespace cathbox::collision {

namespace {

using detail::Obb;
using detail::TreeData;

constexpr std::uint32_t kLeafSize = 4;
constexpr std::size_t kMaxWideDepth = 60;  // keeps the query stacks (3 * depth + 4) bounded

std::atomic<std::uint64_t> g_next_tree_id{1};

std::string validate(const vessel::SurfaceMesh& mesh) {
  if (mesh.triangles.size() % 3 != 0)
    return "surface_mesh.triangles: size " + std::to_string(mesh.triangles.size()) +
           " is not a multiple of 3";
  if (mesh.triangles.empty()) return "surface_mesh.triangles: empty mesh";
  if (mesh.triangle_count() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max() / 4))
    return "surface_mesh.triangles: too many triangles";
  if (mesh.triangle_regions.size() != mesh.triangle_count())
    return "surface_mesh.triangle_regions: size " + std::to_string(mesh.triangle_regions.size()) +
           ", expected one per triangle (" + std::to_string(mesh.triangle_count()) + ")";
  for (std::size_t i = 0; i < mesh.positions_mm.size(); ++i) {
    const glm::vec3& p = mesh.positions_mm[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return "surface_mesh.positions_mm[" + std::to_string(i) + "]: not finite";
  }
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    if (mesh.triangles[i] >= mesh.positions_mm.size())
      return "surface_mesh.triangles[" + std::to_string(i) + "]: vertex index " +
             std::to_string(mesh.triangles[i]) + " out of range (vertex count " +
             std::to_string(mesh.positions_mm.size()) + ")";
  }
  return {};
}

}  // namespace

}  // namespace cathbox::collision

// Moments and box fits (one translation unit: see builder_faces.hpp).
#include "builder_boxes.hpp"

namespace cathbox::collision {

namespace detail {

struct BinaryNode {
  Obb box;                  // valid once has_box (only nodes that become wide-node children)
  Moments moments;          // of the centroids (region nodes)
  bool has_box = false;
  std::int32_t left = -1;
  std::int32_t right = -1;
  std::uint32_t begin = 0;  // faces order[begin, end) (leaves and region nodes)
  std::uint32_t end = 0;
  std::uint32_t count = 0;  // triangles below
  bool in_region = false;   // inside one region's subtree (including its root)
  std::int32_t block = -1;  // a leaf's TriangleBlock in its tree (in the cache: the last tree's)
  [[nodiscard]] bool leaf() const { return left < 0; }
};

// What a triangle's corners alone decide: whether it is kept, its unit normal and its corner
// angles (the pseudo-normal weights).
struct FaceFacts {
  glm::dvec3 normal{0.0};
  double angle[3] = {0.0, 0.0, 0.0};
  bool kept = false;
};

// One region's part of a build, kept for the next one (TreeCache).
struct CachedRegion {
  vessel::FaceRegion region;
  std::vector<glm::vec3> corners;    // 3 per triangle (degenerate ones too), in mesh order
  std::vector<FaceFacts> facts;      // per triangle, in mesh order
  bool has_subtree = false;          // false: every triangle degenerate
  std::vector<std::uint32_t> order;  // the kept triangles' final order, as indices into their mesh order
  std::int32_t node_first = 0;       // its subtree: RegionCache::nodes[node_first, node_end), preorder
  std::int32_t node_end = 0;
  std::uint32_t item_first = 0;      // the nodes' item ranges start here
  std::size_t leaves = 0;
};

struct RegionCache {
  double scale_mm = -1.0;  // boxes carry a margin from the mesh's scale: reuse needs the same
  std::vector<CachedRegion> regions;
  std::vector<BinaryNode> nodes;  // the last build's binary nodes, boxes fitted
  std::shared_ptr<const TreeData> tree;  // the last build's tree (its leaf blocks)
  std::size_t reused = 0;
  std::size_t built = 0;
};

}  // namespace detail

namespace {

using detail::BinaryNode;
using detail::CachedRegion;
using detail::FaceFacts;
using detail::RegionCache;

std::uint64_t region_key(const vessel::FaceRegion& r) {
  return (static_cast<std::uint64_t>(r.kind) << 32) | static_cast<std::uint32_t>(r.id);
}

class Builder {
 public:
  Builder(const vessel::SurfaceMesh& mesh, TreeData& data, RegionCache* cache) : mesh_(mesh), d_(data), cache_(cache) {}

  std::string run() {
    copy_mesh();
    match_cache();
    find_kept_faces();
    if (kept_.empty()) return "surface_mesh.triangles: every triangle is degenerate (zero area)";
    build_topology();
    group_regions();
    const std::int32_t root = build_groups(0, static_cast<std::uint32_t>(region_roots_.size()));
    d_.nodes.reserve(kept_.size() / 6 + 8);
    d_.blocks.reserve(leaf_count_);
    gather_corners();
    std::size_t depth = 0;
    make_wide(root, 1, depth);
    if (depth > kMaxWideDepth) return "surface_mesh: tree too deep (" + std::to_string(depth) + ")";
    d_.stats.triangles = kept_.size();
    d_.stats.degenerate_dropped = mesh_.triangle_count() - kept_.size();
    d_.stats.regions = region_roots_.size();
    d_.stats.wide_nodes = d_.nodes.size();
    d_.stats.leaves = d_.blocks.size();
    d_.stats.depth = depth;
    keep_regions();
    return {};
  }

 private:
  void copy_mesh();

  glm::dvec3 corner(std::uint32_t face, int k) const { return d_.positions[d_.triangles[3 * face + k]]; }

  // Faces with the cache: every region's triangles (degenerate ones too) in mesh order, and the
  // cached region holding the same floats in the same order, if any; a face of such a region
  // takes its FaceFacts from there.
  void match_cache();

  // Kept (non-degenerate) faces in mesh order, their unit normals and corner angles: computed,
  // or taken from the cache for the faces of unchanged regions (the same values: they depend on
  // the corners only).
  void find_kept_faces();

  FaceFacts face_facts(std::uint32_t f) const;

  // Vertex -> kept triangles, neighbours across edges, valences, pseudo-normals.
  void build_topology();

  // Outgoing half-edges per vertex: u -> w of face f, vertex v's in [start[v], start[v + 1]).
  struct VertexHalfEdges {
    struct HalfEdge {
      std::uint32_t to;
      std::uint32_t face;
    };
    std::vector<std::uint32_t> start;
    std::vector<HalfEdge> out;
  };

  [[nodiscard]] VertexHalfEdges outgoing_half_edges() const;

  // The opposite of u -> w is w -> u; another u -> w means a non-manifold or flipped face.
  void link_opposites(const VertexHalfEdges& edges);

  // Angle-weighted pseudo-normals of the vertices.
  void accumulate_vertex_normals();

  // Counting sort of the kept faces by region; one subtree per region.
  void group_regions();

  // The corners of the items in their final order, so that fitting a box reads one contiguous
  // run instead of gathering vertices through the index array (the box fits read every corner
  // once per wide level; float copies: half the memory traffic, same values).
  // Only the built regions' items: a reused subtree has its boxes.
  void gather_corners();

  template <typename Fn>
  void for_each_corner(std::uint32_t begin, std::uint32_t end, Fn&& fn) const {
    for (std::size_t c = 3 * std::size_t{begin}; c < 3 * std::size_t{end}; ++c) fn(glm::dvec3(corners_[c]));
  }

  // A leaf's few triangles lie on a patch of the wall: its box is thin along their mean normal
  // and aligned in the patch with the longest edge (no eigen-solve needed).
  Obb leaf_box(std::uint32_t begin, std::uint32_t end) const;

  // Boxes are fitted only for the nodes that become children of wide nodes: region nodes take
  // the principal axes of their centroids (of their corners for leaves, which have few), group
  // nodes enclose their children's boxes.
  const Obb& ensure_box(std::int32_t id);

  std::int32_t add_node(const BinaryNode& node) {
    bnodes_.push_back(node);
    return static_cast<std::int32_t>(bnodes_.size() - 1);
  }

  // Moments of the centroids of items [begin, end), accumulated relative to the first centroid:
  // in float for the many small nodes (the split and box axes need no more), in double for big
  // ones.
  Moments centroid_moments(std::uint32_t begin, std::uint32_t end) const {
    return end - begin <= 4096 ? centroid_moments_as<float>(begin, end) : centroid_moments_as<double>(begin, end);
  }

  template <typename Real>
  Moments centroid_moments_as(std::uint32_t begin, std::uint32_t end) const {
    MomentSums<Real> sums;
    for (std::uint32_t i = begin; i < end; ++i) sums.add(glm::vec<3, Real>(items_[i].centroid));
    return sums.moments();
  }

  // Median split along the principal axis of the centroids, keeping the left part a multiple of
  // the leaf size.
  std::int32_t build_region(std::uint32_t begin, std::uint32_t end);

  // Region r's subtree from the cache, when its triangles are the cached ones (same floats, same
  // order): the items take the cached order and the nodes are appended with their boxes.
  bool reuse_region(std::size_t r);

  // This build's regions into the cache (after the boxes are fitted), replacing the last's.
  void keep_regions();

  // Regions [first, last) of region_roots_: split along the longest spread of their centres,
  // balancing triangle counts. Group boxes enclose the children's boxes.
  std::int32_t build_groups(std::uint32_t first, std::uint32_t last);

  Obb enclose(const Obb& a, const Obb& b) const;

  static void set_box_lane(detail::BoxLanes& lanes, int lane, const Obb& box);

  static void set_empty_box_lane(detail::BoxLanes& lanes, int lane);

  // A leaf's block: copied from the last tree for a leaf of a reused region (only the face
  // numbers can differ), else written.
  std::int32_t make_block(std::int32_t id);

  // Flattens binary node b into a 4-wide node: opens the largest children until there are four,
  // never opening a region's root from the group levels above it.
  std::int32_t make_wide(std::int32_t b, std::size_t level, std::size_t& depth);

  const vessel::SurfaceMesh& mesh_;
  TreeData& d_;
  std::vector<std::uint32_t> kept_;
  // Kept faces, grouped by region and then ordered by the splits; leaves are runs of them.
  struct Item {
    float key;  // projection on the current split axis
    glm::vec3 centroid;
    std::uint32_t face;
  };
  std::vector<Item> items_;
  std::vector<glm::vec3> corners_;  // 3 per item, in items_ order (filled before the boxes)
  std::size_t leaf_count_ = 0;
  std::vector<BinaryNode> bnodes_;
  std::vector<std::int32_t> region_roots_;
  std::vector<glm::dvec3> region_centres_;
  // Per region (in order of first appearance): its key, first item, mesh-order corners, node
  // range and leaves, and whether it came from the cache; per face, its place in its region.
  RegionCache* cache_ = nullptr;
  std::vector<vessel::FaceRegion> keys_;
  std::vector<std::uint32_t> region_first_;
  // With the cache, per region of any triangle (in order of first appearance): its key, its
  // triangles grouped (all_faces_[all_first_[a], all_first_[a + 1]), mesh order), their corners,
  // the cached region holding the same ones (-1: none), and per face where its facts come from.
  std::vector<vessel::FaceRegion> all_keys_;
  std::vector<std::uint32_t> all_first_, all_faces_;
  std::vector<std::vector<glm::vec3>> all_corners_;
  std::vector<std::int32_t> all_hit_;
  std::unordered_map<std::uint64_t, std::int32_t> hit_of_key_;
  std::vector<const FaceFacts*> source_;
  std::vector<FaceFacts> facts_;  // per face
  std::vector<std::int32_t> region_node_first_, region_node_end_;
  std::vector<std::size_t> region_leaves_;
  std::vector<bool> region_reused_;
  std::vector<std::uint32_t> local_;
  std::vector<Item> scratch_items_;
};

}  // namespace
}  // namespace cathbox::collision

// Builder's steps, by topic (one translation unit: see builder_faces.hpp).
#include "builder_faces.hpp"
#include "builder_splits.hpp"
#include "builder_region_reuse.hpp"
#include "builder_flatten.hpp"

namespace cathbox::collision {

TreeCache::TreeCache() : data_(std::make_unique<detail::RegionCache>()) {}
TreeCache::~TreeCache() = default;
TreeCache::TreeCache(TreeCache&&) noexcept = default;
TreeCache& TreeCache::operator=(TreeCache&&) noexcept = default;
std::size_t TreeCache::reused_regions() const { return data_ ? data_->reused : 0; }
std::size_t TreeCache::built_regions() const { return data_ ? data_->built : 0; }

TreeBuild TreeBuilder::build(const vessel::SurfaceMesh& mesh, const BuildOptions& options, TreeCache* cache) {
  if (std::string error = validate(mesh); !error.empty()) return base::Error{std::move(error)};
  if (!(options.coherence_margin_mm >= 0.0) || !std::isfinite(options.coherence_margin_mm)) {
    return base::Error{"build_options.coherence_margin_mm: must be finite and >= 0"};
  }
  auto data = std::make_shared<TreeData>();
  data->id = g_next_tree_id.fetch_add(1);
  data->coherence_margin_mm = options.coherence_margin_mm;
  if (cache != nullptr && !cache->data_) cache->data_ = std::make_unique<detail::RegionCache>();
  Builder builder(mesh, *data, cache != nullptr ? cache->data_.get() : nullptr);
  if (std::string error = builder.run(); !error.empty()) return base::Error{std::move(error)};
  if (cache != nullptr) cache->data_->tree = data;  // its blocks, for the next build's reused leaves
  return ObbTree(std::move(data));
}

TreeBuild ObbTree::build(const vessel::SurfaceMesh& mesh, const BuildOptions& options) {
  return TreeBuilder::build(mesh, options);
}

TreeBuild ObbTree::build(const vessel::SurfaceMesh& mesh, const BuildOptions& options, TreeCache& cache) {
  return TreeBuilder::build(mesh, options, &cache);
}

}  // namespace cathbox::collision
