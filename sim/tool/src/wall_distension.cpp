#include "tool/wall_distension.hpp"

#include <algorithm>

namespace cathbox::tool {
namespace {

double median_of(std::vector<double>& values) {
  if (values.empty()) return 0.0;
  const auto mid = values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2);
  std::nth_element(values.begin(), mid, values.end());
  return *mid;
}

}  // namespace

double median_radius_mm(const vessel::VesselModel& model) {
  std::vector<double> radii;
  radii.reserve(model.point_count());
  for (const vessel::Segment& s : model.segments) {
    for (const vessel::CenterlinePoint& p : s.points) radii.push_back(p.radius_mm);
  }
  return median_of(radii);
}

WallDistension::WallDistension(const vessel::VesselModel& model, const ArterialWall& wall) {
  std::vector<double> radii;
  for (const vessel::Segment& s : model.segments) {
    radii.clear();
    for (const vessel::CenterlinePoint& p : s.points) radii.push_back(p.radius_mm);
    const double r = median_of(radii);
    if (!(r > 0.0)) continue;
    ids_.push_back(s.id);
    radius_mm_.push_back(r);
    compliance_.push_back(1.0 / WallShell(wall, r).hoop_stiffness_kPa_per_mm());
  }
  for (const double c : compliance_) junction_compliance_ += c;
  if (!compliance_.empty()) junction_compliance_ /= static_cast<double>(compliance_.size());
}

void WallDistension::apply(double pressure_kPa, DisplacedWall& wall) const {
  wall.set_uniform_mm(junction_compliance_ * pressure_kPa);
  for (std::size_t i = 0; i < ids_.size(); ++i) wall.set_segment_mm(ids_[i], compliance_[i] * pressure_kPa);
}

double WallDistension::displacements_mm(double pressure_kPa, std::span<double> out) const {
  for (std::size_t i = 0; i < ids_.size() && i < out.size(); ++i) out[i] = compliance_[i] * pressure_kPa;
  return junction_compliance_ * pressure_kPa;
}

}  // namespace cathbox::tool
