#include "tool/mesh_wall.hpp"

#include <cmath>

namespace cathbox::tool {

MeshWall::MeshWall(collision::ObbTree tree, std::size_t hint_slots)
    : tree_(std::move(tree)), hints_(hint_slots > 0 ? hint_slots : 1) {}

bool MeshWall::probe(const WallProbe& probe, WallHint& hint, WallContact& out) const {
  if (hint.index >= hints_.size()) {
    // A node's first query takes the next slot (round robin when more nodes than slots).
    hint.index = next_slot_;
    next_slot_ = (next_slot_ + 1) % static_cast<std::uint32_t>(hints_.size());
    hints_[hint.index].reset();
  }
  const double reach = probe.radius_mm + probe.range_mm;
  if (!(reach >= 0.0) || !std::isfinite(reach)) return false;
  const std::optional<collision::ClosestPoint> cp = tree_.closest_point(probe.center_mm, reach, hints_[hint.index]);
  if (!cp) return false;
  out.point_mm = cp->point_mm;
  out.normal = cp->normal;
  out.distance_mm = -cp->signed_distance_mm;
  switch (cp->region.kind) {
    case vessel::RegionKind::kSegment:
    case vessel::RegionKind::kCap: out.segment = cp->region.id; break;
    case vessel::RegionKind::kJunction: out.segment = kJunction; break;
  }
  return true;
}

}  // namespace cathbox::tool
