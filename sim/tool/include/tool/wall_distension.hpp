#pragma once
// The compliant wall distended by the blood pressure: every segment of a vessel model is a
// WallShell (arterial_wall.hpp) of the territory's material at the segment's own radius — the
// median of its centreline radii, which for an imported surface is the distance from the
// skeleton to the surface — and a change P of the transmural pressure moves its wall by Laplace's
// w = P R^2 / (E h) = P / k (the shell's hoop stiffness; far from ends and loads the long-cylinder
// equation reduces to it). The displacement goes into a DisplacedWall, the field the collision
// queries read (the tree is never refit); junction faces take the mean of the segments'.
//
// Sized at construction: apply() and displacements_mm() allocate nothing (one multiply per
// segment), so the haptic loop may call them every tick. Units: mm, kPa.
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "tool/arterial_wall.hpp"
#include "tool/displaced_wall.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

// The median of every centreline point's radius of the model (0 for an empty model): one
// lumen radius for a whole case (compliant_contact.hpp's stiffness), taken from the graph.
[[nodiscard]] double median_radius_mm(const vessel::VesselModel& model);

class WallDistension {
 public:
  WallDistension(const vessel::VesselModel& model, const ArterialWall& wall);

  [[nodiscard]] std::size_t segment_count() const { return ids_.size(); }
  [[nodiscard]] std::int32_t segment_id(std::size_t index) const { return ids_[index]; }
  [[nodiscard]] double radius_mm(std::size_t index) const { return radius_mm_[index]; }
  // R^2 / (E h) of segment `index` (mm per kPa).
  [[nodiscard]] double compliance_mm_per_kPa(std::size_t index) const { return compliance_[index]; }

  // Every segment's wall (and the junctions') moved by Laplace's distension at `pressure_kPa`
  // over the pressure the wall was imaged or meshed at.
  void apply(double pressure_kPa, DisplacedWall& wall) const;
  // The same displacements per segment, in model order (out.size() >= segment_count()), and the
  // junctions' as the return value: for renderers that move the drawn surface.
  double displacements_mm(double pressure_kPa, std::span<double> out) const;

 private:
  std::vector<std::int32_t> ids_;
  std::vector<double> radius_mm_;
  std::vector<double> compliance_;
  double junction_compliance_ = 0.0;
};

}  // namespace cathbox::tool
