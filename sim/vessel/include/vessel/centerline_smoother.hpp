#pragma once
// Smoothing of each segment's centerline (positions and radii) before the control mesh is built.
// End points are fixed; since segments meet only at their ends, junction points are fixed too.
// With `snap_junctions`, ends that meet at a junction are first moved onto the junction's centre
// so the branches share one point.
//
//  Taubin (default): one pass is v += lambda L(v), then v += mu L(v), with the umbrella operator
//    L(v)_l = (v_{l-1} + v_{l+1}) / 2 - v_l, lambda = 0.5, mu = -0.5263 (all points of a step
//    updated at once). A sinusoid of frequency k = 1 - cos(theta) (theta: turning per point) is
//    scaled by (1 - lambda k)(1 - mu k) per pass: 0 at the Nyquist frequency (point-to-point
//    noise), >= 1 below k = 0.1 (smooth curves and radius profiles), never above 1.00066.
//    The radius step is weighted by min(1, (0.25 r / h)^2) (h: mean spacing of the point to its
//    neighbours): a sampled radius profile is smoothed where points are dense enough (h <= r/4)
//    that noise and a radius change two radii long are different frequencies; where they are
//    sparser a few points may be the whole stenosis or bulge, and the radius is left as it is
//    (outliers are the radius filter's job, radius_filter.hpp).
//  Moving average (thesis 3.2.3.2, equation 2), in place:
//    v_1 = u_1,  v_l = (v_{l-1} + 2 u_l + u_{l+1}) / 4,  v_L = u_L.
#include "vessel/mesh_options.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

[[nodiscard]] VesselModel smooth_centerlines(const VesselModel& model, const VesselGraph& graph, int passes,
                                             bool snap_junctions = true,
                                             SmoothingMethod method = SmoothingMethod::kTaubin);

// One pass of the (1,2,1) filter on a polyline (in place, as in equation (2) of the thesis).
void smooth_polyline(std::vector<CenterlinePoint>& points);

// One Taubin lambda|mu pass on a polyline (end points fixed).
void taubin_polyline(std::vector<CenterlinePoint>& points);

constexpr double kTaubinLambda = 0.5;
constexpr double kTaubinMu = -0.5263;
constexpr double kRadiusSmoothingSpacing = 0.25;  // in radii: denser points get the full radius step

}  // namespace cathbox::vessel
