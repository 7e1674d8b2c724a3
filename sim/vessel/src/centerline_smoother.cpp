#include "vessel/centerline_smoother.hpp"

namespace cathbox::vessel {

void smooth_polyline(std::vector<CenterlinePoint>& points) {
  if (points.size() < 3) return;
  CenterlinePoint previous = points.front();  // v_{l-1}, already filtered
  for (std::size_t l = 1; l + 1 < points.size(); ++l) {
    CenterlinePoint v;
    v.pos_mm = (previous.pos_mm + 2.0 * points[l].pos_mm + points[l + 1].pos_mm) * 0.25;
    v.radius_mm = (previous.radius_mm + 2.0 * points[l].radius_mm + points[l + 1].radius_mm) * 0.25;
    points[l] = v;
    previous = v;
  }
}

VesselModel smooth_centerlines(const VesselModel& model, const VesselGraph& graph, int passes, bool snap_junctions) {
  VesselModel out = model;
  for (std::size_t j = 0; snap_junctions && j < graph.junctions().size(); ++j) {
    const Junction& junction = graph.junctions()[j];
    for (const SegmentEnd& e : junction.ends) {
      auto& points = out.segments[e.segment].points;
      if (points.empty()) continue;
      (e.at_end ? points.back() : points.front()).pos_mm = junction.center_mm;
    }
  }
  for (Segment& s : out.segments) {
    for (int pass = 0; pass < passes; ++pass) smooth_polyline(s.points);
  }
  return out;
}

}  // namespace cathbox::vessel
