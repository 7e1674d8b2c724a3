#include "tree_builder.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include <glm/geometric.hpp>

#include "obb_fit.hpp"
#include "tree_data.hpp"

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

// Box around points given by for_each(fn): principal axes of `axis_points` (centroids for
// faces, the corners themselves for groups), extents of all `points`.
template <typename AxisPoints, typename Points>
Obb fit_box(AxisPoints&& axis_points, Points&& points, double scale_mm) {
  glm::dvec3 mean{0.0};
  double n = 0.0;
  axis_points([&](const glm::dvec3& p) {
    mean += p;
    n += 1.0;
  });
  mean /= n;
  double cov[6] = {0, 0, 0, 0, 0, 0};
  axis_points([&](const glm::dvec3& p) {
    const glm::dvec3 q = p - mean;
    cov[0] += q.x * q.x;
    cov[1] += q.y * q.y;
    cov[2] += q.z * q.z;
    cov[3] += q.x * q.y;
    cov[4] += q.x * q.z;
    cov[5] += q.y * q.z;
  });
  Obb box;
  detail::principal_axes(cov, box.axis);
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  points([&](const glm::dvec3& p) {
    const glm::dvec3 x = p - mean;
    const glm::dvec3 l{glm::dot(x, box.axis[0]), glm::dot(x, box.axis[1]), glm::dot(x, box.axis[2])};
    lo = glm::min(lo, l);
    hi = glm::max(hi, l);
  });
  // Centre back in world space; the margin covers storing the box in floats.
  const glm::dvec3 mid = (lo + hi) * 0.5;
  box.center = mean + mid.x * box.axis[0] + mid.y * box.axis[1] + mid.z * box.axis[2];
  const glm::dvec3 half = (hi - lo) * 0.5;
  const double margin = 16.0 * std::numeric_limits<float>::epsilon() * (scale_mm + half.x + half.y + half.z);
  box.half = half + glm::dvec3{margin};
  return box;
}

struct BinaryNode {
  Obb box;
  std::int32_t left = -1;
  std::int32_t right = -1;
  std::uint32_t begin = 0;  // faces order[begin, end) (leaves and region nodes)
  std::uint32_t end = 0;
  std::uint32_t count = 0;  // triangles below
  bool in_region = false;   // inside one region's subtree (including its root)
  [[nodiscard]] bool leaf() const { return left < 0; }
};

class Builder {
 public:
  Builder(const vessel::SurfaceMesh& mesh, TreeData& data) : mesh_(mesh), d_(data) {}

  std::string run() {
    copy_mesh();
    find_kept_faces();
    if (kept_.empty()) return "surface_mesh.triangles: every triangle is degenerate (zero area)";
    build_topology();
    group_regions();
    const std::int32_t root = build_groups(0, static_cast<std::uint32_t>(region_roots_.size()));
    d_.nodes.reserve(kept_.size() / 6 + 8);
    d_.blocks.reserve(kept_.size() / 3 + 8);
    std::size_t depth = 0;
    make_wide(root, 1, depth);
    if (depth > kMaxWideDepth) return "surface_mesh: tree too deep (" + std::to_string(depth) + ")";
    d_.stats.triangles = kept_.size();
    d_.stats.degenerate_dropped = mesh_.triangle_count() - kept_.size();
    d_.stats.regions = region_roots_.size();
    d_.stats.wide_nodes = d_.nodes.size();
    d_.stats.leaves = d_.blocks.size();
    d_.stats.depth = depth;
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

  void find_kept_faces() {
    const std::size_t n = mesh_.triangle_count();
    d_.face_normals.assign(n, glm::dvec3{0.0});
    kept_.reserve(n);
    for (std::uint32_t f = 0; f < n; ++f) {
      const glm::dvec3 a = corner(f, 0);
      const glm::dvec3 b = corner(f, 1);
      const glm::dvec3 c = corner(f, 2);
      const glm::dvec3 cr = glm::cross(b - a, c - a);
      const double area2 = glm::length(cr);
      const double longest = std::max({glm::dot(b - a, b - a), glm::dot(c - a, c - a),
                                       glm::dot(c - b, c - b)});
      if (!(area2 > 1e-12 * longest)) continue;
      d_.face_normals[f] = cr / area2;
      kept_.push_back(f);
    }
  }

  // Vertex -> kept triangles, neighbours across edges, valences, pseudo-normals.
  void build_topology() {
    const std::size_t nv = d_.positions.size();
    std::vector<std::uint32_t> start(nv + 1, 0);
    for (std::uint32_t f : kept_)
      for (int k = 0; k < 3; ++k) ++start[d_.triangles[3 * f + k] + 1];
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<std::uint32_t> incident(start[nv]);
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t f : kept_)
      for (int k = 0; k < 3; ++k) incident[fill[d_.triangles[3 * f + k]]++] = f;

    d_.valence.resize(nv);
    for (std::size_t v = 0; v < nv; ++v) d_.valence[v] = start[v + 1] - start[v];

    d_.opposite.assign(d_.triangles.size(), -1);
    bool closed = true;
    bool oriented = true;
    for (std::uint32_t f : kept_) {
      for (int k = 0; k < 3; ++k) {
        const std::uint32_t u = d_.triangles[3 * f + k];
        const std::uint32_t w = d_.triangles[3 * f + (k + 1) % 3];
        int found = 0;
        for (std::uint32_t i = start[u]; i < start[u + 1]; ++i) {
          const std::uint32_t g = incident[i];
          if (g == f) continue;
          for (int j = 0; j < 3; ++j) {
            const std::uint32_t gu = d_.triangles[3 * g + j];
            const std::uint32_t gw = d_.triangles[3 * g + (j + 1) % 3];
            if (gu == w && gw == u) {
              if (found == 0) d_.opposite[3 * f + k] = static_cast<std::int32_t>(g);
              ++found;
            } else if (gu == u && gw == w) {
              oriented = false;
              if (found == 0) d_.opposite[3 * f + k] = static_cast<std::int32_t>(g);
              ++found;
            }
          }
        }
        if (found != 1) closed = false;
      }
    }
    d_.stats.closed = closed;
    d_.stats.consistently_oriented = oriented;

    d_.vertex_normals.assign(nv, glm::dvec3{0.0});
    for (std::uint32_t f : kept_) {
      for (int k = 0; k < 3; ++k) {
        const glm::dvec3 p = corner(f, k);
        const glm::dvec3 e1 = glm::normalize(corner(f, (k + 1) % 3) - p);
        const glm::dvec3 e2 = glm::normalize(corner(f, (k + 2) % 3) - p);
        const double angle = std::acos(std::clamp(glm::dot(e1, e2), -1.0, 1.0));
        d_.vertex_normals[d_.triangles[3 * f + k]] += angle * d_.face_normals[f];
      }
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
    for (std::size_t i = 0; i < kept_.size(); ++i) {
      const vessel::FaceRegion r = d_.regions[kept_[i]];
      const std::uint64_t key = (static_cast<std::uint64_t>(r.kind) << 32) |
                                static_cast<std::uint32_t>(r.id);
      auto [it, inserted] = index.try_emplace(key, static_cast<std::uint32_t>(counts.size()));
      if (inserted) counts.push_back(0);
      region_of[i] = it->second;
      ++counts[it->second];
    }
    std::vector<std::uint32_t> first(counts.size() + 1, 0);
    for (std::size_t r = 0; r < counts.size(); ++r) first[r + 1] = first[r] + counts[r];
    order_.resize(kept_.size());
    std::vector<std::uint32_t> fill(first.begin(), first.end() - 1);
    for (std::size_t i = 0; i < kept_.size(); ++i) order_[fill[region_of[i]]++] = kept_[i];

    centroids_.resize(d_.triangles.size() / 3);
    for (std::uint32_t f : kept_)
      centroids_[f] = (corner(f, 0) + corner(f, 1) + corner(f, 2)) / 3.0;
    keys_.resize(kept_.size());

    for (std::size_t r = 0; r < counts.size(); ++r) {
      const std::int32_t root = build_region(first[r], first[r + 1]);
      region_roots_.push_back(root);
      glm::dvec3 mean{0.0};
      for (std::uint32_t i = first[r]; i < first[r + 1]; ++i) mean += centroids_[order_[i]];
      region_centres_.push_back(mean / static_cast<double>(counts[r]));
    }
  }

  // Box of the faces order[begin, end): principal axes of the centroids, extents of the corners.
  Obb fit_faces(std::uint32_t begin, std::uint32_t end) const {
    return fit_box(
        [&](auto&& fn) {
          for (std::uint32_t i = begin; i < end; ++i) fn(centroids_[order_[i]]);
        },
        [&](auto&& fn) {
          for (std::uint32_t i = begin; i < end; ++i)
            for (int k = 0; k < 3; ++k) fn(corner(order_[i], k));
        },
        d_.scale_mm);
  }

  std::int32_t add_node(const BinaryNode& node) {
    bnodes_.push_back(node);
    return static_cast<std::int32_t>(bnodes_.size() - 1);
  }

  // Median split along the longest box axis, keeping the left part a multiple of the leaf size.
  std::int32_t build_region(std::uint32_t begin, std::uint32_t end) {
    BinaryNode node;
    node.box = fit_faces(begin, end);
    node.begin = begin;
    node.end = end;
    node.count = end - begin;
    node.in_region = true;
    const std::int32_t id = add_node(node);
    const std::uint32_t n = end - begin;
    if (n <= kLeafSize) return id;
    int longest = 0;
    for (int k = 1; k < 3; ++k)
      if (node.box.half[k] > node.box.half[longest]) longest = k;
    const glm::dvec3 axis = node.box.axis[longest];
    for (std::uint32_t i = begin; i < end; ++i)
      keys_[i] = {glm::dot(centroids_[order_[i]], axis), order_[i]};
    std::uint32_t left = ((n / 2 + kLeafSize / 2) / kLeafSize) * kLeafSize;
    left = std::clamp(left, kLeafSize, n - 1);
    std::nth_element(keys_.begin() + begin, keys_.begin() + begin + left, keys_.begin() + end);
    for (std::uint32_t i = begin; i < end; ++i) order_[i] = keys_[i].second;
    const std::int32_t l = build_region(begin, begin + left);
    const std::int32_t r = build_region(begin + left, end);
    bnodes_[id].left = l;
    bnodes_[id].right = r;
    return id;
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
    node.box = enclose(bnodes_[l].box, bnodes_[r].box);
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
    return fit_box(each, each, d_.scale_mm);
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

  std::int32_t make_block(const BinaryNode& leaf) {
    detail::TriangleBlock block{};
    for (int lane = 0; lane < 4; ++lane) {
      const std::uint32_t i = leaf.begin + static_cast<std::uint32_t>(lane);
      if (i >= leaf.end) {
        for (int c = 0; c < 3; ++c)
          for (int r : {detail::kRowA, detail::kRowB, detail::kRowC}) block.row[r + c][lane] = 1e30f;
        block.row[detail::kRowN][lane] = 1.0f;
        block.face[lane] = -1;
        continue;
      }
      const std::uint32_t f = order_[i];
      block.face[lane] = static_cast<std::int32_t>(f);
      block.region = d_.regions[f];
      const glm::dvec3 a = corner(f, 0);
      const glm::dvec3 e0 = corner(f, 1) - a;
      const glm::dvec3 e1 = corner(f, 2) - a;
      const double g00 = glm::dot(e0, e0);
      const double g01 = glm::dot(e0, e1);
      const double g11 = glm::dot(e1, e1);
      const double det = g00 * g11 - g01 * g01;
      const bool sliver = !(det > 1e-6 * g00 * g11);
      const glm::dvec3 u = sliver ? glm::dvec3{0.0} : (g11 * e0 - g01 * e1) / det;
      const glm::dvec3 v = sliver ? glm::dvec3{0.0} : (g00 * e1 - g01 * e0) / det;
      const glm::dvec3 n = sliver ? glm::dvec3{0.0} : d_.face_normals[f];
      for (int c = 0; c < 3; ++c) {
        block.row[detail::kRowA + c][lane] = static_cast<float>(a[c]);
        block.row[detail::kRowB + c][lane] = static_cast<float>(a[c] + e0[c]);
        block.row[detail::kRowC + c][lane] = static_cast<float>(a[c] + e1[c]);
        block.row[detail::kRowN + c][lane] = static_cast<float>(n[c]);
        block.row[detail::kRowU + c][lane] = static_cast<float>(u[c]);
        block.row[detail::kRowV + c][lane] = static_cast<float>(v[c]);
      }
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
        child = c.leaf() ? -1 - make_block(c) : make_wide(slots[lane], level + 1, depth);
        set_box_lane(d_.nodes[w].boxes, lane, bnodes_[slots[lane]].box);
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
  std::vector<std::uint32_t> order_;
  std::vector<glm::dvec3> centroids_;
  std::vector<std::pair<double, std::uint32_t>> keys_;
  std::vector<BinaryNode> bnodes_;
  std::vector<std::int32_t> region_roots_;
  std::vector<glm::dvec3> region_centres_;
};

}  // namespace

TreeBuild TreeBuilder::build(const vessel::SurfaceMesh& mesh, const BuildOptions& options) {
  TreeBuild result;
  if (std::string error = validate(mesh); !error.empty()) {
    result.error = std::move(error);
    return result;
  }
  if (!(options.coherence_margin_mm >= 0.0) || !std::isfinite(options.coherence_margin_mm)) {
    result.error = "build_options.coherence_margin_mm: must be finite and >= 0";
    return result;
  }
  auto data = std::make_shared<TreeData>();
  data->id = g_next_tree_id.fetch_add(1);
  data->coherence_margin_mm = options.coherence_margin_mm;
  Builder builder(mesh, *data);
  if (std::string error = builder.run(); !error.empty()) {
    result.error = std::move(error);
    return result;
  }
  result.tree = ObbTree(std::move(data));
  return result;
}

TreeBuild ObbTree::build(const vessel::SurfaceMesh& mesh, const BuildOptions& options) {
  return TreeBuilder::build(mesh, options);
}

}  // namespace cathbox::collision
