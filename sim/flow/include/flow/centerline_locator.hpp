#pragma once
// Nearest place on the vessel centrelines to a point (for an injection at the catheter tip):
// the segment, the arc length along it, and the distance. A linear scan of the centreline
// pieces (about a thousand for the neuro case), run when an injection starts, not per tick.
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/vessel_model.hpp"

namespace cathbox::flow {

struct CenterlinePosition {
  std::uint32_t segment = 0;  // index into the model's segments
  double arc_mm = 0.0;        // from the segment's first point
  double distance_mm = 0.0;   // from the query point to the centreline
};

class CenterlineLocator {
 public:
  explicit CenterlineLocator(const vessel::VesselModel& model);

  // The model must have at least one segment.
  [[nodiscard]] CenterlinePosition nearest(const glm::dvec3& point_mm) const;
  // The nearest place on one segment's centreline.
  [[nodiscard]] CenterlinePosition nearest_on(std::uint32_t segment, const glm::dvec3& point_mm) const;
  // The centreline point and radius at an arc position (clamped to the segment).
  [[nodiscard]] glm::dvec3 point_at(std::uint32_t segment, double arc_mm) const;
  [[nodiscard]] double radius_at(std::uint32_t segment, double arc_mm) const;
  [[nodiscard]] double length_mm(std::uint32_t segment) const { return arcs_[segment].back(); }

 private:
  const vessel::VesselModel* model_;
  std::vector<std::vector<double>> arcs_;
};

}  // namespace cathbox::flow
