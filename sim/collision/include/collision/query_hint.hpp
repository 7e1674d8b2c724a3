#pragma once
// Per-tool-node memory for the coherent queries. A tool node moves little between two 1 ms
// steps, so the hint keeps a copy of the wall triangles nearest to where it was last filled:
// every triangle closer than `radius` to `origin` (at most kCapacity, nearest first, in the
// tree's 4-wide float layout). A later query near that origin searches only that copy, and a
// cheap test (needed reach + distance moved <= radius) proves nothing else can change the
// answer; otherwise the hint is refilled from the tree. Results are exactly those of the cold
// queries. Keep one hint per tool node; queries never allocate. About 11 KB each (the triangle
// copies stay untouched until the first refill).
#include <cstdint>

#include "vessel/surface_mesh.hpp"

namespace cathbox::collision {

class ObbTree;
class HintCache;

class QueryHint {
 public:
  static constexpr int kCapacity = 128;  // triangles
  static constexpr int kBlocks = kCapacity / 4;
  static constexpr int kBlockBytes = 320;  // one 4-wide triangle block of the tree

  void reset() { radius_mm_ = -1.0; count_ = 0; tree_id_ = 0; }
  [[nodiscard]] bool valid() const { return radius_mm_ >= 0.0; }
  [[nodiscard]] int triangle_count() const { return count_; }
  [[nodiscard]] double radius_mm() const { return radius_mm_; }
  // How many queries were answered from the cache / needed a refill (for tuning and tests).
  [[nodiscard]] std::uint32_t hits() const { return hits_; }
  [[nodiscard]] std::uint32_t refills() const { return refills_; }

 private:
  friend class ObbTree;
  friend class HintCache;
  double origin_mm_[3] = {0.0, 0.0, 0.0};
  double radius_mm_ = -1.0;  // every triangle within this distance of origin is cached
  std::uint64_t tree_id_ = 0;
  int count_ = 0;
  std::uint32_t hits_ = 0;
  std::uint32_t refills_ = 0;
  float block_min_mm_[kBlocks] = {};  // distance from origin to the nearest triangle of each block
  vessel::FaceRegion regions_[kCapacity] = {};
  // The cached triangles, filled on refill (left uninitialised until then).
  alignas(64) unsigned char blocks_[kBlocks][kBlockBytes];
};

}  // namespace cathbox::collision
