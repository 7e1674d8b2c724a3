#pragma once
// The vessel wall as a triangle mesh, queried through the collision module's OBB tree (cold
// queries by default, optionally one coherent hint per tool node). Not thread-safe (the hints
// are per simulator); the tree itself is shared and immutable. Only built with the collision
// module (CATHBOX_TOOL_HAS_COLLISION).
#include <cstdint>
#include <vector>

#include "collision/obb_tree.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::tool {

class MeshWall final : public WallModel {
 public:
  // Segment reported for wall points on a junction between segments.
  static constexpr std::int32_t kJunction = -2;

  // hint_slots > 0 enables the tree's coherent queries, one hint per tool node (round robin
  // over that many slots). Off by default: the hinted closest-point query of the collision
  // module at this revision can crash after ~10^5 coherent queries along a walk (reported);
  // the rod re-probes only nodes near the wall, so cold queries cost little.
  explicit MeshWall(collision::ObbTree tree, std::size_t hint_slots = 0);

  [[nodiscard]] bool probe(const WallProbe& probe, WallHint& hint, WallContact& out) const override;
  [[nodiscard]] const collision::ObbTree& tree() const { return tree_; }

 private:
  collision::ObbTree tree_;
  mutable std::vector<collision::QueryHint> hints_;
  mutable std::uint32_t next_slot_ = 0;
};

}  // namespace cathbox::tool
