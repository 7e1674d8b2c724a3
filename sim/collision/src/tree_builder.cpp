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

namespace detail {

// Mean and covariance (xx, yy, zz, xy, xz, yz) of points, in one pass.
struct Moments {
  glm::dvec3 mean{0.0};
  double cov[6] = {0, 0, 0, 0, 0, 0};
};

}  // namespace detail

namespace {

using detail::Moments;

// Sums of points relative to the first one (shifted sums keep the precision), in Real.
template <typename Real>
struct MomentSums {
  using Vec = glm::vec<3, Real>;
  Vec origin{Real(0)};
  Vec sum{Real(0)};
  Real sq[6] = {0, 0, 0, 0, 0, 0};
  double n = 0.0;

  void add(const Vec& p) {
    if (n == 0.0) origin = p;
    const Vec q = p - origin;
    sum += q;
    sq[0] += q.x * q.x;
    sq[1] += q.y * q.y;
    sq[2] += q.z * q.z;
    sq[3] += q.x * q.y;
    sq[4] += q.x * q.z;
    sq[5] += q.y * q.z;
    n += 1.0;
  }
  [[nodiscard]] Moments moments() const {
    const glm::dvec3 mq = glm::dvec3(sum) / n;
    Moments m;
    m.mean = glm::dvec3(origin) + mq;
    const double pairs[6][2] = {{mq.x, mq.x}, {mq.y, mq.y}, {mq.z, mq.z}, {mq.x, mq.y}, {mq.x, mq.z}, {mq.y, mq.z}};
    for (int k = 0; k < 6; ++k) m.cov[k] = static_cast<double>(sq[k]) / n - pairs[k][0] * pairs[k][1];
    return m;
  }
};

template <typename Points>
Moments moments_of(Points&& points) {
  MomentSums<double> sums;
  points([&](const glm::dvec3& p) { sums.add(p); });
  return sums.moments();
}

// Dominant eigenvector of a covariance by a few power iterations (the split direction).
glm::dvec3 dominant_axis(const double cov[6]) {
  glm::dvec3 v{1.0, 0.0, 0.0};
  if (cov[1] > cov[0] && cov[1] >= cov[2]) v = {0.0, 1.0, 0.0};
  if (cov[2] > cov[0] && cov[2] > cov[1]) v = {0.0, 0.0, 1.0};
  auto apply = [&](const glm::dvec3& x) {
    return glm::dvec3{cov[0] * x.x + cov[3] * x.y + cov[4] * x.z, cov[3] * x.x + cov[1] * x.y + cov[5] * x.z,
                      cov[4] * x.x + cov[5] * x.y + cov[2] * x.z};
  };
  for (int round = 0; round < 3; ++round) {  // three products per normalisation
    const glm::dvec3 w = apply(apply(apply(v)));
    const double len = glm::length(w);
    if (!(len > 0.0) || !std::isfinite(len)) break;
    v = w / len;
  }
  return v;
}

// Box in the orthonormal frame (x, y, z) around all `points` (origin: any point near them); the
// margin covers storing it in floats.
template <typename Points>
Obb box_in_frame(const glm::dvec3& x, const glm::dvec3& y, const glm::dvec3& z, const glm::dvec3& origin,
                 Points&& points, double scale_mm) {
  Obb box;
  box.axis[0] = x;
  box.axis[1] = y;
  box.axis[2] = z;
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  points([&](const glm::dvec3& p) {
    const glm::dvec3 d = p - origin;
    const glm::dvec3 l{glm::dot(d, x), glm::dot(d, y), glm::dot(d, z)};
    lo = glm::min(lo, l);
    hi = glm::max(hi, l);
  });
  const glm::dvec3 mid = (lo + hi) * 0.5;
  box.center = origin + mid.x * x + mid.y * y + mid.z * z;
  const glm::dvec3 half = (hi - lo) * 0.5;
  const double margin = 16.0 * std::numeric_limits<float>::epsilon() * (scale_mm + half.x + half.y + half.z);
  box.half = half + glm::dvec3{margin};
  return box;
}

// Box with the principal axes of `m` around all `points`.
template <typename Points>
Obb box_around(const Moments& m, Points&& points, double scale_mm) {
  glm::dvec3 axes[3];
  detail::principal_axes(m.cov, axes);
  return box_in_frame(axes[0], axes[1], axes[2], m.mean, points, scale_mm);
}

}  // namespace

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
  void copy_mesh() {
    d_.positions.resize(mesh_.positions_mm.size());
    glm::dvec3 max_abs{0.0};
    for (std::size_t i = 0; i < d_.positions.size(); ++i) {
      d_.positions[i] = glm::dvec3(mesh_.positions_mm[i]);
      max_abs = glm::max(max_abs, glm::abs(d_.positions[i]));
    }
    d_.scale_mm = max_abs.x + max_abs.y + max_abs.z;
    d_.triangles = mesh_.triangles;
    d_.regions = mesh_.triangle_regions;
  }

  glm::dvec3 corner(std::uint32_t face, int k) const { return d_.positions[d_.triangles[3 * face + k]]; }

  // Faces with the cache: every region's triangles (degenerate ones too) in mesh order, and the
  // cached region holding the same floats in the same order, if any; a face of such a region
  // takes its FaceFacts from there.
  void match_cache() {
    if (cache_ == nullptr) return;
    const std::size_t n = mesh_.triangle_count();
    std::unordered_map<std::uint64_t, std::uint32_t> index;
    std::vector<std::uint32_t> region_of(n);
    std::vector<std::uint32_t> first(1, 0);
    std::uint64_t last_key = ~0ull;
    std::uint32_t last = 0;
    for (std::size_t f = 0; f < n; ++f) {
      const std::uint64_t key = region_key(d_.regions[f]);
      if (key != last_key) {
        auto [it, inserted] = index.try_emplace(key, static_cast<std::uint32_t>(all_keys_.size()));
        if (inserted) {
          all_keys_.push_back(d_.regions[f]);
          first.push_back(0);
        }
        last_key = key;
        last = it->second;
      }
      region_of[f] = last;
      ++first[last + 1];
    }
    for (std::size_t r = 0; r + 1 < first.size(); ++r) first[r + 1] += first[r];
    std::vector<std::uint32_t> faces(n);
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::uint32_t f = 0; f < n; ++f) faces[fill[region_of[f]]++] = f;
    all_corners_.assign(all_keys_.size(), {});
    all_hit_.assign(all_keys_.size(), -1);
    source_.assign(n, nullptr);
    for (std::size_t r = 0; r < all_keys_.size(); ++r) {
      std::vector<glm::vec3>& corners = all_corners_[r];
      corners.reserve(3 * std::size_t{first[r + 1] - first[r]});
      for (std::uint32_t i = first[r]; i < first[r + 1]; ++i)
        for (std::uint32_t k = 0; k < 3; ++k) corners.push_back(mesh_.positions_mm[d_.triangles[3 * faces[i] + k]]);
      for (std::size_t c = 0; c < cache_->regions.size(); ++c) {
        const CachedRegion& cached = cache_->regions[c];
        if (cached.region == all_keys_[r] && cached.corners.size() == corners.size() &&
            std::memcmp(cached.corners.data(), corners.data(), corners.size() * sizeof(glm::vec3)) == 0) {
          all_hit_[r] = static_cast<std::int32_t>(c);
          break;
        }
      }
      if (all_hit_[r] < 0) continue;
      const std::vector<FaceFacts>& facts = cache_->regions[static_cast<std::size_t>(all_hit_[r])].facts;
      for (std::uint32_t i = first[r]; i < first[r + 1]; ++i) source_[faces[i]] = &facts[i - first[r]];
      hit_of_key_[region_key(all_keys_[r])] = all_hit_[r];
    }
    all_first_ = std::move(first);
    all_faces_ = std::move(faces);
  }

  // Kept (non-degenerate) faces in mesh order, their unit normals and corner angles: computed,
  // or taken from the cache for the faces of unchanged regions (the same values: they depend on
  // the corners only).
  void find_kept_faces() {
    const std::size_t n = mesh_.triangle_count();
    d_.face_normals.resize(n);
    facts_.reserve(n);
    kept_.reserve(n);
    for (std::uint32_t f = 0; f < n; ++f) {
      facts_.push_back(!source_.empty() && source_[f] != nullptr ? *source_[f] : face_facts(f));
      d_.face_normals[f] = facts_.back().normal;
      if (facts_.back().kept) kept_.push_back(f);
    }
  }

  FaceFacts face_facts(std::uint32_t f) const {
    FaceFacts facts;
    const glm::dvec3 a = corner(f, 0);
    const glm::dvec3 b = corner(f, 1);
    const glm::dvec3 c = corner(f, 2);
    const glm::dvec3 cr = glm::cross(b - a, c - a);
    const double area2 = glm::length(cr);
    const double longest = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a),
                                     glm::dot(c - b, c - b)});
    if (!(area2 > 1e-12 * longest)) return facts;
    facts.kept = true;
    facts.normal = cr / area2;
    const glm::dvec3 p[3] = {a, b, c};
    const glm::dvec3 e[3] = {p[1] - p[0], p[2] - p[1], p[0] - p[2]};  // e[k] leaves corner k
    // The largest angle (opposite the longest edge) is pi minus the other two, which atan2
    // gives accurately even for slivers; float precision is plenty for a weight.
    double len[3];
    for (int k = 0; k < 3; ++k) len[k] = glm::dot(e[k], e[k]);
    const int longest_edge = len[0] >= len[1] && len[0] >= len[2] ? 0 : (len[1] >= len[2] ? 1 : 2);
    const int big = (longest_edge + 2) % 3;  // the corner opposite the longest edge
    double sum = 0.0;
    for (int k = 0; k < 3; ++k) {
      if (k == big) continue;
      const glm::dvec3 u = e[k];
      const glm::dvec3 v = -e[(k + 2) % 3];
      facts.angle[k] = std::atan2(static_cast<float>(glm::length(glm::cross(u, v))), static_cast<float>(glm::dot(u, v)));
      sum += facts.angle[k];
    }
    facts.angle[big] = std::max(0.0, 3.14159265358979323846 - sum);
    return facts;
  }

  // Vertex -> kept triangles, neighbours across edges, valences, pseudo-normals.
  void build_topology() {
    const VertexHalfEdges edges = outgoing_half_edges();
    const std::size_t nv = d_.positions.size();
    d_.valence.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) d_.valence[v] = edges.start[v + 1] - edges.start[v];
    link_opposites(edges);
    accumulate_vertex_normals();
  }

  // Outgoing half-edges per vertex: u -> w of face f, vertex v's in [start[v], start[v + 1]).
  struct VertexHalfEdges {
    struct HalfEdge {
      std::uint32_t to;
      std::uint32_t face;
    };
    std::vector<std::uint32_t> start;
    std::vector<HalfEdge> out;
  };

  [[nodiscard]] VertexHalfEdges outgoing_half_edges() const {
    const std::size_t nv = d_.positions.size();
    VertexHalfEdges e;
    e.start.assign(nv + 1, 0);
    for (std::uint32_t f : kept_)
      for (int k = 0; k < 3; ++k) ++e.start[d_.triangles[3 * f + k] + 1];
    for (std::size_t v = 0; v < nv; ++v) e.start[v + 1] += e.start[v];
    e.out.resize(e.start[nv]);
    std::vector<std::uint32_t> fill(e.start.begin(), e.start.end() - 1);
    for (std::uint32_t f : kept_)
      for (int k = 0; k < 3; ++k)
        e.out[fill[d_.triangles[3 * f + k]]++] = {d_.triangles[3 * f + (k + 1) % 3], f};
    return e;
  }

  // The opposite of u -> w is w -> u; another u -> w means a non-manifold or flipped face.
  void link_opposites(const VertexHalfEdges& edges) {
    const auto& start = edges.start;
    const auto& out = edges.out;
    d_.opposite.assign(d_.triangles.size(), -1);
    bool closed = true;
    bool oriented = true;
    for (std::uint32_t f : kept_) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = d_.triangles[3 * f + k];
        const std::uint32_t w = d_.triangles[3 * f + (k + 1) % 3];
        int found = 0;
        for (std::uint32_t i = start[w]; i < start[w + 1]; ++i) {
          if (out[i].to != u) continue;
          if (found++ == 0) d_.opposite[3 * f + k] = static_cast<std::int32_t>(out[i].face);
        }
        for (std::uint32_t i = start[u]; i < start[u + 1]; ++i) {
          if (out[i].to != w || out[i].face == f) continue;
          oriented = false;
          if (found++ == 0) d_.opposite[3 * f + k] = static_cast<std::int32_t>(out[i].face);
        }
        if (found != 1) closed = false;
      }
    }
    d_.stats.closed = closed;
    d_.stats.consistently_oriented = oriented;
  }

  // Angle-weighted pseudo-normals of the vertices.
  void accumulate_vertex_normals() {
    d_.vertex_normals.assign(d_.positions.size(), glm::dvec3{0.0});
    for (std::uint32_t f : kept_) {
      for (int k = 0; k < 3; ++k) d_.vertex_normals[d_.triangles[3 * f + k]] += facts_[f].angle[k] * d_.face_normals[f];
    }
    for (glm::dvec3& n : d_.vertex_normals) {
      const double len = glm::length(n);
      if (len > 0.0) n /= len;
    }
  }

  // Counting sort of the kept faces by region; one subtree per region.
  void group_regions() {
    std::unordered_map<std::uint64_t, std::uint32_t> index;
    std::vector<std::uint32_t> region_of(kept_.size());
    std::vector<std::uint32_t> counts;
    std::uint64_t last_key = ~0ull;
    std::uint32_t last = 0;
    for (std::size_t i = 0; i < kept_.size(); ++i) {
      const vessel::FaceRegion r = d_.regions[kept_[i]];
      const std::uint64_t key = region_key(r);
      if (key != last_key) {  // neighbouring faces mostly share a region
        auto [it, inserted] = index.try_emplace(key, static_cast<std::uint32_t>(counts.size()));
        if (inserted) counts.push_back(0);
        last_key = key;
        last = it->second;
      }
      region_of[i] = last;
      ++counts[last];
    }
    std::vector<std::uint32_t> first(counts.size() + 1, 0);
    for (std::size_t r = 0; r < counts.size(); ++r) first[r + 1] = first[r] + counts[r];
    items_.resize(kept_.size());
    if (cache_ != nullptr) local_.assign(mesh_.triangle_count(), 0);
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < kept_.size(); ++i) {
      const std::uint32_t f = kept_[i];
      const glm::dvec3 c = (corner(f, 0) + corner(f, 1) + corner(f, 2)) / 3.0;
      if (cache_ != nullptr) local_[f] = fill[region_of[i]] - first[region_of[i]];  // its place in its region, mesh order
      items_[fill[region_of[i]]++] = {0.0f, glm::vec3(c), f};
    }
    bnodes_.reserve(2 * (kept_.size() / kLeafSize + counts.size()) + 8);

    keys_.resize(counts.size());
    for (const auto& [key, r] : index) {
      keys_[r] = {static_cast<vessel::RegionKind>(key >> 32), static_cast<std::int32_t>(static_cast<std::uint32_t>(key))};
    }
    region_first_ = first;
    region_node_first_.assign(counts.size(), 0);
    region_node_end_.assign(counts.size(), 0);
    region_leaves_.assign(counts.size(), 0);
    region_reused_.assign(counts.size(), false);
    for (std::size_t r = 0; r < counts.size(); ++r) {
      const std::size_t leaves_before = leaf_count_;
      region_node_first_[r] = static_cast<std::int32_t>(bnodes_.size());
      region_reused_[r] = reuse_region(r);
      const std::int32_t root = region_reused_[r] ? region_node_first_[r] : build_region(first[r], first[r + 1]);
      region_node_end_[r] = static_cast<std::int32_t>(bnodes_.size());
      region_leaves_[r] = leaf_count_ - leaves_before;
      region_roots_.push_back(root);
      glm::dvec3 mean{0.0};
      for (std::uint32_t i = first[r]; i < first[r + 1]; ++i) mean += glm::dvec3(items_[i].centroid);
      region_centres_.push_back(mean / static_cast<double>(counts[r]));
    }
  }

  // The corners of the items in their final order, so that fitting a box reads one contiguous
  // run instead of gathering vertices through the index array (the box fits read every corner
  // once per wide level; float copies: half the memory traffic, same values).
  // Only the built regions' items: a reused subtree has its boxes.
  void gather_corners() {
    corners_.resize(3 * items_.size());
    for (std::size_t r = 0; r < keys_.size(); ++r) {
      if (region_reused_[r]) continue;
      for (std::size_t i = region_first_[r]; i < region_first_[r + 1]; ++i)
        for (std::uint32_t k = 0; k < 3; ++k) corners_[3 * i + k] = mesh_.positions_mm[d_.triangles[3 * items_[i].face + k]];
    }
  }

  template <typename Fn>
  void for_each_corner(std::uint32_t begin, std::uint32_t end, Fn&& fn) const {
    for (std::size_t c = 3 * std::size_t{begin}; c < 3 * std::size_t{end}; ++c) fn(glm::dvec3(corners_[c]));
  }

  // A leaf's few triangles lie on a patch of the wall: its box is thin along their mean normal
  // and aligned in the patch with the longest edge (no eigen-solve needed).
  Obb leaf_box(std::uint32_t begin, std::uint32_t end) const {
    glm::dvec3 normal{0.0};
    glm::dvec3 longest{0.0};
    double longest_sq = -1.0;
    for (std::uint32_t i = begin; i < end; ++i) {
      const std::uint32_t f = items_[i].face;
      const glm::dvec3 a = corner(f, 0), b = corner(f, 1), c = corner(f, 2);
      normal += glm::cross(b - a, c - a);
      for (const glm::dvec3& e : {b - a, c - b, a - c}) {
        const double len = glm::dot(e, e);
        if (len > longest_sq) {
          longest_sq = len;
          longest = e;
        }
      }
    }
    const glm::dvec3 origin = corner(items_[begin].face, 0);
    const double nlen = glm::length(normal);
    glm::dvec3 z = nlen > 0.0 ? normal / nlen : glm::dvec3{0.0, 0.0, 1.0};
    glm::dvec3 x = longest - glm::dot(longest, z) * z;
    const double xlen = glm::length(x);
    if (!(xlen > 1e-12 * std::sqrt(longest_sq))) {
      x = std::abs(z.x) < 0.6 ? glm::dvec3{1, 0, 0} : glm::dvec3{0, 1, 0};
      x = glm::normalize(x - glm::dot(x, z) * z);
    } else {
      x /= xlen;
    }
    return box_in_frame(x, glm::cross(z, x), z, origin, [&](auto&& fn) { for_each_corner(begin, end, fn); },
                        d_.scale_mm);
  }

  // Boxes are fitted only for the nodes that become children of wide nodes: region nodes take
  // the principal axes of their centroids (of their corners for leaves, which have few), group
  // nodes enclose their children's boxes.
  const Obb& ensure_box(std::int32_t id) {
    BinaryNode& node = bnodes_[id];
    if (node.has_box) return node.box;
    const std::uint32_t begin = node.begin;
    const std::uint32_t end = node.end;
    auto corners = [&](auto&& fn) { for_each_corner(begin, end, fn); };
    if (!node.in_region) {
      const Obb a = ensure_box(node.left);
      const Obb b = ensure_box(bnodes_[id].right);
      bnodes_[id].box = enclose(a, b);
    } else if (node.leaf()) {
      bnodes_[id].box = leaf_box(begin, end);
    } else {
      bnodes_[id].box = box_around(node.moments, corners, d_.scale_mm);
    }
    bnodes_[id].has_box = true;
    return bnodes_[id].box;
  }

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
  std::int32_t build_region(std::uint32_t begin, std::uint32_t end) {
    BinaryNode node;
    node.begin = begin;
    node.end = end;
    node.count = end - begin;
    node.in_region = true;
    const std::uint32_t n = end - begin;
    if (n > kLeafSize) {
      node.moments = centroid_moments(begin, end);
    }
    const std::int32_t id = add_node(node);
    if (n <= kLeafSize) {
      ++leaf_count_;
      return id;
    }
    const glm::dvec3 axis = dominant_axis(node.moments.cov);
    const glm::vec3 axis_f(axis);
    for (std::uint32_t i = begin; i < end; ++i) items_[i].key = glm::dot(items_[i].centroid, axis_f);
    std::uint32_t left = ((n / 2 + kLeafSize / 2) / kLeafSize) * kLeafSize;
    left = std::clamp(left, kLeafSize, n - 1);
    std::nth_element(items_.begin() + begin, items_.begin() + begin + left, items_.begin() + end,
                     [](const Item& a, const Item& b) { return a.key < b.key; });
    const std::int32_t l = build_region(begin, begin + left);
    const std::int32_t r = build_region(begin + left, end);
    bnodes_[id].left = l;
    bnodes_[id].right = r;
    return id;
  }

  // Region r's subtree from the cache, when its triangles are the cached ones (same floats, same
  // order): the items take the cached order and the nodes are appended with their boxes.
  bool reuse_region(std::size_t r) {
    if (cache_ == nullptr || cache_->scale_mm != d_.scale_mm) return false;
    const auto found = hit_of_key_.find(region_key(keys_[r]));
    if (found == hit_of_key_.end()) return false;
    const CachedRegion* hit = &cache_->regions[static_cast<std::size_t>(found->second)];
    if (!hit->has_subtree) return false;
    const std::uint32_t first = region_first_[r];
    const std::uint32_t count = region_first_[r + 1] - first;
    scratch_items_.assign(items_.begin() + first, items_.begin() + first + count);
    for (std::uint32_t j = 0; j < count; ++j) items_[first + j] = scratch_items_[hit->order[j]];
    const std::int32_t shift = static_cast<std::int32_t>(bnodes_.size()) - hit->node_first;
    for (std::int32_t k = hit->node_first; k < hit->node_end; ++k) {
      BinaryNode node = cache_->nodes[static_cast<std::size_t>(k)];
      if (node.left >= 0) node.left += shift;
      if (node.right >= 0) node.right += shift;
      node.begin = node.begin - hit->item_first + first;
      node.end = node.end - hit->item_first + first;
      bnodes_.push_back(node);
    }
    leaf_count_ += hit->leaves;
    return true;
  }

  // This build's regions into the cache (after the boxes are fitted), replacing the last's.
  void keep_regions() {
    if (cache_ == nullptr) return;
    // Every region's triangles and facts (moved from the cache when it held them already) ...
    std::vector<CachedRegion> kept(all_keys_.size());
    std::unordered_map<std::uint64_t, std::size_t> slot;
    for (std::size_t a = 0; a < all_keys_.size(); ++a) {
      CachedRegion& c = kept[a];
      c.region = all_keys_[a];
      c.corners = std::move(all_corners_[a]);
      if (all_hit_[a] >= 0) {
        c.facts = std::move(cache_->regions[static_cast<std::size_t>(all_hit_[a])].facts);
      } else {
        c.facts.resize(all_first_[a + 1] - all_first_[a]);
        for (std::uint32_t i = all_first_[a]; i < all_first_[a + 1]; ++i) c.facts[i - all_first_[a]] = facts_[all_faces_[i]];
      }
      slot[region_key(c.region)] = a;
    }
    // ... and the subtrees of those with kept triangles.
    const std::size_t regions = keys_.size();
    std::size_t reused = 0;
    for (std::size_t r = 0; r < regions; ++r) {
      const std::uint32_t first = region_first_[r];
      const std::uint32_t count = region_first_[r + 1] - first;
      CachedRegion& c = kept[slot.at(region_key(keys_[r]))];
      c.has_subtree = true;
      c.node_first = region_node_first_[r];
      c.node_end = region_node_end_[r];
      c.item_first = first;
      c.leaves = region_leaves_[r];
      c.order.resize(count);
      for (std::uint32_t i = 0; i < count; ++i) c.order[i] = local_[items_[first + i].face];
      reused += region_reused_[r] ? 1 : 0;
    }
    cache_->regions = std::move(kept);
    cache_->nodes = std::move(bnodes_);
    cache_->scale_mm = d_.scale_mm;
    cache_->reused = reused;
    cache_->built = regions - reused;
  }

  // Regions [first, last) of region_roots_: split along the longest spread of their centres,
  // balancing triangle counts. Group boxes enclose the children's boxes.
  std::int32_t build_groups(std::uint32_t first, std::uint32_t last) {
    if (last - first == 1) return region_roots_[first];
    glm::dvec3 lo{std::numeric_limits<double>::infinity()};
    glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
    for (std::uint32_t i = first; i < last; ++i) {
      lo = glm::min(lo, region_centres_[i]);
      hi = glm::max(hi, region_centres_[i]);
    }
    const glm::dvec3 ext = hi - lo;
    const int axis = ext.x >= ext.y && ext.x >= ext.z ? 0 : (ext.y >= ext.z ? 1 : 2);
    std::vector<std::uint32_t> idx(last - first);
    for (std::uint32_t i = 0; i < idx.size(); ++i) idx[i] = first + i;
    std::sort(idx.begin(), idx.end(), [&](std::uint32_t x, std::uint32_t y) {
      return region_centres_[x][axis] < region_centres_[y][axis];
    });
    std::vector<std::int32_t> roots(idx.size());
    std::vector<glm::dvec3> centres(idx.size());
    std::uint64_t total = 0;
    for (std::size_t i = 0; i < idx.size(); ++i) {
      roots[i] = region_roots_[idx[i]];
      centres[i] = region_centres_[idx[i]];
      total += bnodes_[roots[i]].count;
    }
    std::copy(roots.begin(), roots.end(), region_roots_.begin() + first);
    std::copy(centres.begin(), centres.end(), region_centres_.begin() + first);
    std::uint64_t acc = 0;
    std::uint32_t split = first + 1;
    for (std::uint32_t i = first; i + 1 < last; ++i) {
      acc += bnodes_[region_roots_[i]].count;
      split = i + 1;
      if (2 * acc >= total) break;
    }
    const std::int32_t l = build_groups(first, split);
    const std::int32_t r = build_groups(split, last);
    BinaryNode node;
    node.left = l;
    node.right = r;
    node.count = bnodes_[l].count + bnodes_[r].count;
    node.in_region = false;
    return add_node(node);
  }

  Obb enclose(const Obb& a, const Obb& b) const {
    glm::dvec3 pts[16];
    int n = 0;
    for (const Obb* box : {&a, &b})
      for (int i = 0; i < 8; ++i)
        pts[n++] = box->center + ((i & 1) ? 1.0 : -1.0) * box->half.x * box->axis[0] +
                   ((i & 2) ? 1.0 : -1.0) * box->half.y * box->axis[1] +
                   ((i & 4) ? 1.0 : -1.0) * box->half.z * box->axis[2];
    auto each = [&](auto&& fn) {
      for (const glm::dvec3& p : pts) fn(p);
    };
    return box_around(moments_of(each), each, d_.scale_mm);
  }

  static void set_box_lane(detail::BoxLanes& lanes, int lane, const Obb& box) {
    for (int c = 0; c < 3; ++c) {
      lanes.row[c][lane] = static_cast<float>(box.center[c]);
      lanes.row[12 + c][lane] = static_cast<float>(box.half[c]);
      for (int k = 0; k < 3; ++k) lanes.row[3 + 3 * k + c][lane] = static_cast<float>(box.axis[k][c]);
    }
  }

  static void set_empty_box_lane(detail::BoxLanes& lanes, int lane) {
    Obb far;
    far.center = glm::dvec3{1e30};
    set_box_lane(lanes, lane, far);
  }

  // A leaf's block: copied from the last tree for a leaf of a reused region (only the face
  // numbers can differ), else written.
  std::int32_t make_block(std::int32_t id) {
    BinaryNode& leaf = bnodes_[id];
    const std::int32_t old = leaf.block;
    leaf.block = static_cast<std::int32_t>(d_.blocks.size());
    if (old >= 0 && cache_ != nullptr && cache_->tree != nullptr) {
      detail::TriangleBlock block = cache_->tree->blocks[static_cast<std::size_t>(old)];
      for (std::uint32_t i = leaf.begin; i < leaf.end; ++i) block.face[i - leaf.begin] = static_cast<std::int32_t>(items_[i].face);
      d_.blocks.push_back(block);
      return leaf.block;
    }
    detail::TriangleBlock block{};
    for (int lane = 0; lane < 4; ++lane) {
      const std::uint32_t i = leaf.begin + static_cast<std::uint32_t>(lane);
      if (i >= leaf.end) {
        detail::set_empty_triangle_lane(block, lane);
        continue;
      }
      const std::uint32_t f = items_[i].face;
      block.region = d_.regions[f];
      detail::set_triangle_lane(block, lane, corner(f, 0), corner(f, 1), corner(f, 2), d_.face_normals[f],
                                static_cast<std::int32_t>(f));
    }
    d_.blocks.push_back(block);
    return static_cast<std::int32_t>(d_.blocks.size() - 1);
  }

  // Flattens binary node b into a 4-wide node: opens the largest children until there are four,
  // never opening a region's root from the group levels above it.
  std::int32_t make_wide(std::int32_t b, std::size_t level, std::size_t& depth) {
    depth = std::max(depth, level);
    std::int32_t slots[4];
    int count = 0;
    const BinaryNode& self = bnodes_[b];
    if (self.leaf()) {
      slots[count++] = b;
    } else {
      slots[count++] = self.left;
      slots[count++] = self.right;
    }
    while (count < 4) {
      int pick = -1;
      for (int i = 0; i < count; ++i) {
        const BinaryNode& c = bnodes_[slots[i]];
        if (c.leaf() || c.in_region != self.in_region) continue;
        if (pick < 0 || c.count > bnodes_[slots[pick]].count) pick = i;
      }
      if (pick < 0) break;
      const BinaryNode& opened = bnodes_[slots[pick]];
      slots[pick] = opened.left;
      slots[count++] = opened.right;
    }
    const std::int32_t w = static_cast<std::int32_t>(d_.nodes.size());
    d_.nodes.emplace_back();
    for (int lane = 0; lane < 4; ++lane) {
      std::int32_t child = detail::kEmptySlot;
      if (lane < count) {
        const BinaryNode& c = bnodes_[slots[lane]];
        child = c.leaf() ? -1 - make_block(slots[lane]) : make_wide(slots[lane], level + 1, depth);
        set_box_lane(d_.nodes[w].boxes, lane, ensure_box(slots[lane]));
      } else {
        set_empty_box_lane(d_.nodes[w].boxes, lane);
      }
      d_.nodes[w].child[lane] = child;
    }
    return w;
  }

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
