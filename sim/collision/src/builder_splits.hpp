#pragma once
// TreeBuilder's Builder, the binary tree: the kept faces grouped by region, each region split at
// the median along its centroids' principal axis, the regions grouped by their centres; boxes
// fitted only for the nodes that become children of wide nodes.
// Part of tree_builder.cpp's translation unit (see builder_faces.hpp).
namespace cathbox::collision {
namespace {

// Counting sort of the kept faces by region; one subtree per region.
inline void Builder::group_regions() {
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
inline void Builder::gather_corners() {
  corners_.resize(3 * items_.size());
  for (std::size_t r = 0; r < keys_.size(); ++r) {
    if (region_reused_[r]) continue;
    for (std::size_t i = region_first_[r]; i < region_first_[r + 1]; ++i)
      for (std::uint32_t k = 0; k < 3; ++k) corners_[3 * i + k] = mesh_.positions_mm[d_.triangles[3 * items_[i].face + k]];
  }
}

// A leaf's few triangles lie on a patch of the wall: its box is thin along their mean normal
// and aligned in the patch with the longest edge (no eigen-solve needed).
inline Obb Builder::leaf_box(std::uint32_t begin, std::uint32_t end) const {
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
inline const Obb& Builder::ensure_box(std::int32_t id) {
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

// Median split along the principal axis of the centroids, keeping the left part a multiple of
// the leaf size.
inline std::int32_t Builder::build_region(std::uint32_t begin, std::uint32_t end) {
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

// Regions [first, last) of region_roots_: split along the longest spread of their centres,
// balancing triangle counts. Group boxes enclose the children's boxes.
inline std::int32_t Builder::build_groups(std::uint32_t first, std::uint32_t last) {
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

inline Obb Builder::enclose(const Obb& a, const Obb& b) const {
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

}  // namespace
}  // namespace cathbox::collision
