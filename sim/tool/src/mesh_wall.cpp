#include "tool/mesh_wall.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::tool {

MeshWall::MeshWall(collision::ObbTree tree, std::size_t hint_slots, std::shared_ptr<const WallSurface> surface)
    : tree_(std::move(tree)), hints_(hint_slots), touching_(hint_slots, 0), surface_(std::move(surface)) {
  if (surface_ && !surface_->model.segments.empty() && hint_slots > 0) {
    // The axis reads the surface's model, which surface_ keeps alive.
    axis_ = std::make_shared<const LumenAxis>(surface_->model);
    axis_hints_.resize(hint_slots);
  }
  const auto slots = static_cast<std::uint32_t>(hint_slots);
  const std::uint32_t second = slots >= 2 ? std::max<std::uint32_t>(1, slots / 4) : 0;
  pool_start_[1] = slots - second;
  pool_start_[2] = slots;
}

// A node's first query in its thread's pool takes the next slot of that pool (round robin when
// more nodes than slots). False for a pool without slots (pool 1 of a one-slot wall): the query
// goes cold rather than share pool 0's slot, which the other thread may be using.
bool MeshWall::take_slot(WallHint& hint) const {
  const int pool = probe_pool();
  const std::uint32_t lo = pool_start_[pool];
  const std::uint32_t hi = pool_start_[pool + 1];
  if (hi <= lo) return false;
  if (hint.index >= lo && hint.index < hi) return true;
  hint.index = lo + next_slot_[pool];
  next_slot_[pool] = (next_slot_[pool] + 1) % (hi - lo);
  ++cold_[pool];
  hints_[hint.index].reset();
  touching_[hint.index] = 0;
  if (!axis_hints_.empty()) axis_hints_[hint.index] = AxisHint{};
  return true;
}

bool MeshWall::probe(const WallProbe& probe, WallHint& hint, WallContact& out) const {
  const bool coherent = !hints_.empty() && take_slot(hint);
  if (probe.lumen_axis && axis_) {
    AxisHint cold;
    const LumenAxis::Answer a = axis_->probe(probe, coherent ? axis_hints_[hint.index] : cold, out);
    if (a != LumenAxis::Answer::kNone) return a == LumenAxis::Answer::kWall;
  }
  const double reach = probe.radius_mm + probe.range_mm;
  if (!(reach >= 0.0) || !std::isfinite(reach)) return false;
  const double touch = probe.radius_mm + probe.margin_mm;
  // A node that touched the wall at its last probe most likely still does: one sphere query
  // within `touch` then gives both its contacts and its closest point (the nearest of the
  // same candidates); when nothing is that close, the closest point is looked for as usual.
  std::optional<collision::ClosestPoint> cp;
  std::array<collision::Contact, 3> contacts;
  std::size_t count = 0;
  const bool fused = fused_ && probe.second_wall && coherent && touching_[hint.index] != 0 && touch <= reach;
  if (fused) count = tree_.sphere_contacts(probe.center_mm, touch, contacts, hints_[hint.index], cp);
  if (!cp) {
    cp = coherent ? tree_.closest_point(probe.center_mm, reach, hints_[hint.index]) : tree_.closest_point(probe.center_mm, reach);
  }
  if (coherent) touching_[hint.index] = cp && cp->distance_mm < touch ? 1 : 0;
  if (!cp) return false;
  out.point_mm = cp->point_mm;
  // The direction between the centre and the closest point is the gradient of the distance:
  // continuous across the mesh's creases, where face and edge normals jump. The feature's
  // pseudo-normal serves only when the centre sits on the wall.
  if (cp->distance_mm > 1e-6) {
    const glm::dvec3 towards_wall = (cp->point_mm - probe.center_mm) / cp->distance_mm;
    out.normal = cp->signed_distance_mm <= 0.0 ? towards_wall : -towards_wall;
  } else {
    out.normal = cp->normal;
  }
  out.distance_mm = -cp->signed_distance_mm;
  // A node in a crease touches two faces; with one plane it would slip from one to the other.
  out.has_second = false;
  if (probe.second_wall && (cp->distance_mm < touch || cp->signed_distance_mm > 0.0)) {
    // (After a fused query that found nothing within `touch`, there are no contacts either.)
    if (!fused) {
      count = coherent ? tree_.sphere_contacts(probe.center_mm, touch, contacts, hints_[hint.index])
                       : tree_.sphere_contacts(probe.center_mm, touch, contacts);
    }
    for (std::size_t i = 0; i < count; ++i) {
      const glm::dvec3 normal = -contacts[i].normal;
      if (glm::dot(normal, out.normal) < kCreaseSameFaceCos && glm::dot(normal, out.normal) > -0.5) {
        out.has_second = true;
        out.second_point_mm = contacts[i].wall_point_mm;
        out.second_normal = normal;
        break;
      }
    }
  }
  switch (cp->region.kind) {
    case vessel::RegionKind::kSegment:
    case vessel::RegionKind::kCap: out.segment = cp->region.id; break;
    case vessel::RegionKind::kJunction: out.segment = kJunction; break;
  }
  return true;
}

}  // namespace cathbox::tool
