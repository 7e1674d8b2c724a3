#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

std::optional<std::size_t> VesselModel::index_of(std::int32_t id) const {
  for (std::size_t i = 0; i < segments.size(); ++i) {
    if (segments[i].id == id) return i;
  }
  return std::nullopt;
}

std::size_t VesselModel::point_count() const {
  std::size_t n = 0;
  for (const Segment& s : segments) n += s.points.size();
  return n;
}

}  // namespace cathbox::vessel
