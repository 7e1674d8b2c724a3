#include "lumen.hpp"

#include <algorithm>

namespace cathbox::flow {

ArcPiece piece_at(const std::vector<double>& arcs, double arc_mm) {
  if (arc_mm <= arcs.front()) return {0, 0.0};
  if (arc_mm >= arcs.back()) return {arcs.size() - 2, 1.0};
  const auto it = std::upper_bound(arcs.begin(), arcs.end(), arc_mm);
  const std::size_t j = static_cast<std::size_t>(it - arcs.begin()) - 1;
  const double span = arcs[j + 1] - arcs[j];
  return {j, span > 0.0 ? (arc_mm - arcs[j]) / span : 0.0};
}

double radius_at_mm(const vessel::Segment& s, const std::vector<double>& arcs, double arc_mm) {
  const ArcPiece p = piece_at(arcs, arc_mm);
  return s.points[p.j].radius_mm + p.t * (s.points[p.j + 1].radius_mm - s.points[p.j].radius_mm);
}

}  // namespace cathbox::flow
