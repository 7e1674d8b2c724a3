#pragma once
// The vessel wall as a triangle mesh, queried through the collision module's OBB tree with one
// coherent hint per tool node. Not thread-safe (the hints are per simulator); the tree itself
// is shared and immutable.
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "collision/obb_tree.hpp"
#include "tool/lumen_axis.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::tool {

// A facet met near a node's closest one is a crease's second face when its outward normal turns
// from the first's by more than this cosine (and less than a fold back, > -0.5); nearer, it is the
// same face again (MeshWall's probe, and a rod keeping a crease's plane within a solve).
inline constexpr double kCreaseSameFaceCos = 0.995;

class MeshWall final : public WallModel {
 public:
  // Segment reported for wall points on a junction between segments.
  static constexpr std::int32_t kJunction = -2;

  // One coherent hint per probed tool node (a node's first probe takes the next of hint_slots,
  // round robin when more nodes than slots; results equal the cold queries either way). The
  // slots are allocated here, never per step; a slot's ~4.4 KB cut of the tree is first
  // written when that slot is used. hint_slots = 0 gives cold queries. The last quarter of the
  // slots is probe pool 1's (wall_model.hpp: the released coils' thread), the rest pool 0's; a
  // node probed from the other pool takes a slot of that pool. A wall of one slot has none for
  // pool 1: its probes there go cold (the same answers), never into pool 0's slot.
  static constexpr std::size_t kDefaultHintSlots = 4096;
  explicit MeshWall(collision::ObbTree tree, std::size_t hint_slots = kDefaultHintSlots,
                    std::shared_ptr<const WallSurface> surface = {});

  // A probe with lumen_axis (and a surface to read the centrelines from) is answered by the
  // tubes round the centrelines (LumenAxis), with the node's own axis hint; the mesh otherwise.
  [[nodiscard]] bool probe(const WallProbe& probe, WallHint& hint, WallContact& out) const override;
  // Slots a node's query took afresh in pool `pool` (its cut reset: a cold query; tests, benches).
  [[nodiscard]] std::uint64_t cold_slots(int pool) const { return pool >= 0 && pool < kProbePools ? cold_[pool] : 0; }
  // A node that touched the wall at its last probe is probed with one sphere query that also
  // gives its closest point (ObbTree::sphere_contacts with `nearest`), instead of a closest
  // point and then a sphere query; the answers are the same. Off: always the two queries (for
  // the tests and benchmarks that compare the two).
  void set_fused_probes(bool on) { fused_ = on; }
  [[nodiscard]] const collision::ObbTree& tree() const { return tree_; }
  [[nodiscard]] std::shared_ptr<const WallSurface> surface() const override { return surface_; }

 private:
  bool take_slot(WallHint& hint) const;
  collision::ObbTree tree_;
  mutable std::vector<collision::QueryHint> hints_;
  mutable std::vector<std::uint8_t> touching_;  // per slot: the last probe found the wall within touch
  bool fused_ = true;
  std::uint32_t pool_start_[kProbePools + 1] = {};  // pool p's slots: [pool_start_[p], pool_start_[p + 1])
  mutable std::uint32_t next_slot_[kProbePools] = {};
  mutable std::uint64_t cold_[kProbePools] = {};  // per pool, written by its thread alone
  std::shared_ptr<const WallSurface> surface_;
  std::shared_ptr<const LumenAxis> axis_;       // of surface_'s model; null without one
  mutable std::vector<AxisHint> axis_hints_;    // per slot, as hints_
};

}  // namespace cathbox::tool
