#pragma once
// Where the junction fit (junction_fit.hpp) moves one limit position: the nearest point of each
// branch's tube, and the weighted move onto the nearest of them.
#include <cstddef>
#include <limits>
#include <optional>
#include <utility>
#include <vector>

#include <glm/vec3.hpp>

#include "junction_fit.hpp"

namespace cathbox::vessel::detail {

// The nearest point of one branch's tube to a point.
struct Nearest {
  double signed_distance = std::numeric_limits<double>::infinity();  // to the (scaled) tube, < 0 inside
  glm::dvec3 direction{0.0};                                          // from the axis to the point
  double radius = 0.0;                                                // the tube's (scaled) radius there
  double arc = 0.0;                                                   // of the foot, from the junction end
};

// What the search for the nearest tubes reuses from vertex to vertex.
struct TubeSearch {
  std::vector<Nearest> nearest;
  std::vector<std::pair<double, std::size_t>> order;
};

// The move of a limit position onto its nearest tube, along that tube's direction.
struct FitMove {
  double move_mm = 0.0;
  glm::dvec3 direction{0.0};
};

// The weighted move of the limit position `at` of a vertex of `branch` (-1: the patch) onto the
// nearest of the junction's tubes (the header's weights); nothing for a point inside another
// branch's tube, or where the weight is 0.
[[nodiscard]] std::optional<FitMove> fit_move(const std::vector<JunctionFit::Axis>& axes, int branch, const glm::dvec3& at,
                                              TubeSearch& search);

}  // namespace cathbox::vessel::detail
