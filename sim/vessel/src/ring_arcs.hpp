#pragma once
// Where a segment's rings go along its smoothed centreline (RingPlacement::kAdaptive): a ring at
// every HCLM point, rings added where the radius changes fast, and the spacing next to those
// graded (ring_arcs.cpp).
#include <vector>

#include "centerline_polyline.hpp"

namespace cathbox::vessel::detail {

// The arc positions of the rings between the trimmed ends a and b (a < b), increasing.
void adaptive_ring_arcs(const Polyline& pl, double a, double b, std::vector<double>& arcs);

// Splits each span next to a span of added rings (added[i]: the span from arcs[i] to arcs[i + 1])
// until it is at most `growth` (> 1) times that span; the pieces count as added.
void grade_ring_spacing(std::vector<double>& arcs, std::vector<char>& added, double growth);

}  // namespace cathbox::vessel::detail
