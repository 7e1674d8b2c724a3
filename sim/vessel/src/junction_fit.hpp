#pragma once
// Fits the limit surface of long junction patches to the tubes of their branches.
//
// A junction patch is the convex hull of the rings that meet there, and the rings must be pulled
// back until each lies behind every other ring's plane. Where two branches meet at a narrow
// angle (15-25 degrees, as the vertebral arteries into the basilar) that is ~10 radii from the
// junction centre, and a handful of hull faces then span the whole stretch where the branches run
// side by side: their limit surface pinches one branch and bulges the other by ~10 %.
//
// For every junction where a branch's ring sits more than kFitTrimRadii of its radius from the
// junction end, each vertex of the patch's triangles is moved radially onto the tube of the
// branch it is nearest to (the branch's smoothed centreline, Catmull-Rom between points, radius
// linear between points), by the weight w = smoothstep((d2 - d1) / (kFitBlendRadii r1)) where d1,
// d2 are the vertex's signed distances to the nearest and second nearest tube: where two tubes
// are about as near (the crotch between branches, the centre) nothing moves, so the hull's
// bridge between the branches stays; on a branch's outer side the surface lands on its tube. The
// same holds where the two nearest tubes lie on the same side of the vertex (above two branches
// side by side), and the weight fades out for vertices further than kFitFullRadii..kFitMaxMoveRadii
// from every tube (the bridge between branches that have parted).
// The tube's vertices just beyond the ring follow, the weight fading to 0 kFitTubeFadeRadii
// further out, so the moved patch joins the tube without a step. The moved vertices' normals are
// then the area-weighted normals of their triangles.
#include <cstddef>

#include "vessel/control_mesh.hpp"
#include "vessel/surface_mesh.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel::detail {

constexpr double kFitTrimRadii = 1.5;   // a junction is fitted when a ring is further out than this
constexpr double kFitBlendRadii = 0.5;  // d2 - d1 over which the move fades in
constexpr double kFitFullRadii = 0.3;     // vertices this near their tube (in its radii) move all the way,
constexpr double kFitMaxMoveRadii = 0.6;  // those further than this not at (fading in between)
constexpr double kFitTubeFadeRadii = 1.5;  // beyond the ring, the tube's vertices follow over this
constexpr double kFitSameSide = 0.5;      // cosine above which two tubes' directions count as the same side

struct JunctionFitReport {
  std::size_t junctions = 0;  // junctions fitted
  std::size_t vertices = 0;   // vertices moved
  double max_move_mm = 0.0;
};

// `smoothed`/`graph`/`control` are the model, graph and control mesh `mesh` was built from.
JunctionFitReport fit_junction_patches(SurfaceMesh& mesh, const VesselModel& smoothed, const VesselGraph& graph,
                                       const ControlMesh& control);

}  // namespace cathbox::vessel::detail
