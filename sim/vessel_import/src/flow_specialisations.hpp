// The flow's specialisations of CGAL 5.5's Mean_curvature_flow_skeletonization (surface_skeleton.cpp
// runs the flow; flow_specialisations.cpp defines them): the Voronoi poles in the
// inexact-constructions kernel, one contraction step that tests each pole once, and the order of
// the edges the flow collapses. Include it before anything instantiates the flow: an explicit
// specialisation must be declared before its first use in every translation unit.
#pragma once

#include <algorithm>
#include <cstddef>
#include <functional>

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mean_curvature_flow_skeletonization.h>
#include <CGAL/Surface_mesh.h>

// CGAL 5.5's flow keeps the edges it will collapse (`collapse_short_edges`) in a
// std::set<edge_descriptor> of its Polyhedron meso-skeleton, whose operator< compares the
// halfedges' addresses: which short edge collapses first, and so which thin branches survive,
// followed the heap layout (another build, another file order, another process: another graph).
// Here the set orders edges by their halfedges' ids instead, which the flow loop in
// surface_skeleton.cpp numbers in the mesh's own list order before every collapse pass (the pass
// creates no halfedge, so the ids stay unique while the set lives).
namespace cathbox::vessel_import::skeleton_order {
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Skeletonization = CGAL::Mean_curvature_flow_skeletonization<CGAL::Surface_mesh<Kernel::Point_3>>;
using Meso = Skeletonization::Meso_skeleton;
using MesoEdge = boost::graph_traits<Meso>::edge_descriptor;
}  // namespace cathbox::vessel_import::skeleton_order

// Defined in flow_specialisations.cpp (what each does is written there).
template <>
void cathbox::vessel_import::skeleton_order::Skeletonization::compute_voronoi_pole();
template <>
void cathbox::vessel_import::skeleton_order::Skeletonization::contract_geometry();
template <>
void cathbox::vessel_import::skeleton_order::Skeletonization::compute_incident_angle();

template <>
struct std::less<cathbox::vessel_import::skeleton_order::MesoEdge> {
  bool operator()(const cathbox::vessel_import::skeleton_order::MesoEdge& a,
                  const cathbox::vessel_import::skeleton_order::MesoEdge& b) const {
    return key(a) < key(b);
  }
  static std::size_t key(const cathbox::vessel_import::skeleton_order::MesoEdge& e) {
    return std::min(e.halfedge()->id(), e.halfedge()->opposite()->id());
  }
};
