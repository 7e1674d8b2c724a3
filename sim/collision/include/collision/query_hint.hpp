#pragma once
// Per-tool-node memory for the coherent queries. A tool node moves little between two 1 ms
// steps, so the tree remembers, per node, the few leaves of the tree that lie near it: every leaf
// whose box is closer than `radius` to `origin` (at most kCapacity leaves). The next query near
// that origin searches only those leaves, and a cheap test proves that nothing outside them can
// change the answer; otherwise the query falls back to the whole tree and refills the cache.
// Results are exactly those of the cold queries. Keep one hint per tool node; no allocation.
#include <cstdint>

namespace cathbox::collision {

class ObbTree;
class HintCache;

class QueryHint {
 public:
  static constexpr int kCapacity = 16;  // leaves (of up to 4 triangles each)
  static constexpr int kGroups = kCapacity / 4;

  void reset() { radius_mm_ = -1.0; count_ = 0; tree_id_ = 0; }
  [[nodiscard]] bool valid() const { return radius_mm_ >= 0.0; }
  [[nodiscard]] int leaf_count() const { return count_; }
  [[nodiscard]] double radius_mm() const { return radius_mm_; }
  // How many queries were answered from the cache / needed a refill (for tuning and tests).
  [[nodiscard]] std::uint32_t hits() const { return hits_; }
  [[nodiscard]] std::uint32_t refills() const { return refills_; }

 private:
  friend class ObbTree;
  friend class HintCache;
class HintCache;
  double origin_mm_[3] = {0.0, 0.0, 0.0};
  double radius_mm_ = -1.0;  // every triangle within this distance of origin is cached
  std::uint64_t tree_id_ = 0;
  int count_ = 0;
  std::uint32_t hits_ = 0;
  std::uint32_t refills_ = 0;
  // Boxes of the cached leaves, four per group, lanes side by side (centre 3, axes 9, half 3).
  alignas(16) float boxes_[kGroups][15][4] = {};
  std::int32_t leaves_[kCapacity] = {};
};

}  // namespace cathbox::collision
