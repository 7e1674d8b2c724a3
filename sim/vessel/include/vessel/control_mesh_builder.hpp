#pragma once
// Builds the control mesh from a smoothed model (see control_mesh.hpp for its parts).
//
// Rings: one per HCLM point of a segment (the thesis' count), at the same relative arc-length
// positions; where a segment meets a junction its rings are pulled back (trimmed) until every
// ring at that junction lies strictly behind the plane of every other ring there.
// Frames: rotation-minimising (double reflection), propagated from each component's root
// segment through the junctions, so successive rings do not twist.
// Junctions: the convex hull of the incident rings minus the rings' own discs; its triangles are
// paired into quads by a perfect matching when one exists (for M = 4 and a plain bifurcation
// this gives the thesis' 7 quads). Any number of incident segments works. A junction whose hull
// is no such patch (branches overlap) takes its connectivity from the hull of the branches'
// directions on a sphere (MeshOptions::junction_fallback; ControlMesh::fallback_junctions).
// Caps: a smaller ring beyond a free end plus one M-sided face, which subdivides to a dome.
// Shrink compensation: ring radii are divided by the radius ratio of the periodic cubic
// B-spline through a regular M-gon, the curve a Catmull-Clark tube converges to.
#include <string>

#include "base/result.hpp"
#include "vessel/control_mesh.hpp"
#include "vessel/mesh_options.hpp"
#include "vessel/vessel_graph.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

// The control mesh, or what could not be built (one line naming the junction / segment).
using ControlMeshResult = base::Result<ControlMesh>;

// `smoothed` is the output of smooth_centerlines() for `graph`'s model.
[[nodiscard]] ControlMeshResult build_control_mesh(const VesselModel& smoothed, const VesselGraph& graph,
                                                   const MeshOptions& options);

// One line naming the junctions meshed by the fallback ("1 junction meshed by the spherical-hull
// fallback: junction 3 (segments 5 6 7): branches overlap (...)"); empty when there are none.
[[nodiscard]] std::string fallback_summary(const ControlMesh& mesh);

// Limit radius / control radius of a Catmull-Clark tube with M points per ring (mean of the
// extremes at ring vertices and between them).
[[nodiscard]] double tube_shrink_ratio(int ring_points);

}  // namespace cathbox::vessel
