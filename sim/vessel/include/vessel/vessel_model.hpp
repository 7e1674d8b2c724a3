#pragma once
// The central axis model: the segments of one vessel network, in file order.
#include <cstdint>
#include <optional>
#include <vector>

#include "vessel/segment.hpp"

namespace cathbox::vessel {

struct VesselModel {
  std::vector<Segment> segments;

  // Index into `segments` of the segment with this id, if any (linear search).
  [[nodiscard]] std::optional<std::size_t> index_of(std::int32_t id) const;
  [[nodiscard]] std::size_t point_count() const;
  friend bool operator==(const VesselModel&, const VesselModel&) = default;
};

}  // namespace cathbox::vessel
