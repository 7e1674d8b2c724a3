#pragma once
// TreeBuilder's Builder, last step: the binary tree flattened into 4-wide nodes and leaf blocks.
// Part of tree_builder.cpp's translation unit (see builder_faces.hpp).
namespace cathbox::collision {
namespace {

inline void Builder::set_box_lane(detail::BoxLanes& lanes, int lane, const Obb& box) {
  for (int c = 0; c < 3; ++c) {
    lanes.row[c][lane] = static_cast<float>(box.center[c]);
    lanes.row[12 + c][lane] = static_cast<float>(box.half[c]);
    for (int k = 0; k < 3; ++k) lanes.row[3 + 3 * k + c][lane] = static_cast<float>(box.axis[k][c]);
  }
}

inline void Builder::set_empty_box_lane(detail::BoxLanes& lanes, int lane) {
  Obb far;
  far.center = glm::dvec3{1e30};
  set_box_lane(lanes, lane, far);
}

// A leaf's block: copied from the last tree for a leaf of a reused region (only the face
// numbers can differ), else written.
inline std::int32_t Builder::make_block(std::int32_t id) {
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
inline std::int32_t Builder::make_wide(std::int32_t b, std::size_t level, std::size_t& depth) {
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

}  // namespace
}  // namespace cathbox::collision
