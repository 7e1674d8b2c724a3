// The copy of the lumen that the mean curvature flow runs on, coarsened by collapsing its shortest
// edges to their midpoints (surface_skeleton.cpp; flow_decimation.cpp says how and why).
#pragma once

#include <cstddef>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

namespace cathbox::vessel_import {

using FlowMesh = CGAL::Surface_mesh<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>;

// Collapses the shortest edge, each to its midpoint, until `mesh` (closed, triangulated) has at
// most `faces` triangles or no edge can go. A collapse is skipped when it would break the surface
// (CGAL's link condition) or turn a triangle around the moved vertex over. Ties between equally
// long edges go to the lower edge index, so the result is a function of the mesh alone. The mesh
// is left with its removed elements collected.
void collapse_shortest_edges(FlowMesh& mesh, std::size_t faces);

}  // namespace cathbox::vessel_import
