#pragma once
// Thesis 3.2.3.2 step 1: the (1,2,1) moving-average filter along each segment,
//   v_1 = u_1,  v_l = (v_{l-1} + 2 u_l + u_{l+1}) / 4,  v_L = u_L,
// applied `passes` times to positions and radii. End points are fixed; since segments meet only
// at their ends, junction points are fixed too. With `snap_junctions`, ends that meet at a
// junction are first moved onto the junction's centre so the branches share one point.
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

[[nodiscard]] VesselModel smooth_centerlines(const VesselModel& model, const VesselGraph& graph, int passes,
                                             bool snap_junctions = true);

// One pass of the filter on a polyline (in place, as in equation (2) of the thesis).
void smooth_polyline(std::vector<CenterlinePoint>& points);

}  // namespace cathbox::vessel
