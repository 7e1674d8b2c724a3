#pragma once
// Per-tool-node memory for the coherent queries. A tool node moves little between two 1 ms
// steps, so instead of descending from the root every time, a query starts from a cut of the
// tree taken where the node was when the hint was filled: up to kSlots subtrees (inner nodes or
// leaves, with copies of their boxes) that together hold every wall triangle within `radius` of
// `origin`, the subtrees nearest to the origin opened deepest. A closest-point query also first
// measures the leaf that held its previous answer, which gives a tight bound before any box is
// opened; and the hint remembers how far the wall is known to be from the origin, so a node out
// of a limited query's reach gets its empty answer at once. A cheap test (needed reach +
// distance moved <= radius) proves nothing outside the cut can change the answer; otherwise the
// hint is refilled. Results are exactly those of the cold queries. Keep one hint per tool node;
// queries never allocate. About 4.4 KB each.
#include <cstdint>

namespace cathbox::collision {

class ObbTree;
class HintCache;

class QueryHint {
 public:
  static constexpr int kSlots = 64;  // subtrees in the cut
  static constexpr int kBoxRows = 15;  // one 4-wide box group, as in the tree's nodes

  // User-provided, so value-initialisation (std::vector<QueryHint>(n)) leaves the box copies
  // unwritten instead of zeroing them.
  QueryHint() noexcept {}  // NOLINT(modernize-use-equals-default)

  void reset() { radius_mm_ = -1.0; count_ = 0; tree_id_ = 0; seed_block_ = -1; clear_mm_ = 0.0; }
  [[nodiscard]] bool valid() const { return radius_mm_ >= 0.0; }
  [[nodiscard]] int slot_count() const { return count_; }
  [[nodiscard]] double radius_mm() const { return radius_mm_; }
  // How many queries were answered from the cut / needed a refill (for tuning and tests).
  [[nodiscard]] std::uint32_t hits() const { return hits_; }
  [[nodiscard]] std::uint32_t refills() const { return refills_; }

 private:
  friend class ObbTree;
  friend class HintCache;
  double origin_mm_[3] = {0.0, 0.0, 0.0};
  double radius_mm_ = -1.0;  // every triangle within this distance of origin lies in the cut
  std::uint64_t tree_id_ = 0;
  int count_ = 0;
  std::int32_t seed_block_ = -1;  // leaf block of the last closest-point answer, -1 none
  double clear_mm_ = 0.0;  // no triangle is nearer than this to origin (learnt from answers)
  std::uint32_t hits_ = 0;
  std::uint32_t refills_ = 0;
  std::int32_t slot_[kSlots] = {};  // child slots of the tree (node index or leaf), nearest first
  float group_min_mm_[kSlots / 4] = {};  // float distance from origin to each group's nearest box
  // The slots' boxes, four per group in the tree's lane layout (filled on refill).
  alignas(16) float boxes_[kSlots / 4][kBoxRows][4];
};

}  // namespace cathbox::collision
