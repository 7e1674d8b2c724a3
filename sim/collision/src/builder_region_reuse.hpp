#pragma once
// TreeBuilder's Builder and the TreeCache: a region whose triangles are the cached ones takes its
// subtree from the cache; this build's regions replace the last's.
// Part of tree_builder.cpp's translation unit (see builder_faces.hpp).
namespace cathbox::collision {
namespace {

// Region r's subtree from the cache, when its triangles are the cached ones (same floats, same
// order): the items take the cached order and the nodes are appended with their boxes.
inline bool Builder::reuse_region(std::size_t r) {
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
inline void Builder::keep_regions() {
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

}  // namespace
}  // namespace cathbox::collision
