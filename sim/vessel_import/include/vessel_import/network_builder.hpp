#pragma once
// From centreline polylines to a vessel network (VesselModel): segments between junctions and
// free ends, parents and children, ready for HCLM.
//
// Polylines given by geometry (VTK, Slicer curves) are inserted one after the other into a
// growing network. A point of a new polyline lies on the network when it is within
// kOverlapRadii of its own radius of the network's polylines. The run of such points at the
// polyline's start (and at its end) is shared with the network: VMTK gives one centreline per
// outlet, each running from the inlet and sharing the trunk point for point or nearly so, and
// vmtkbranchextractor splits them where they part; here the shared run is dropped and the rest
// is attached where the run ends, splitting the network's polyline there (or joining its end
// node when that is within kSnapRadii). A polyline whose start touches the network (an
// already-split network: one polyline per branch, sharing end points) is attached the same way;
// one lying entirely on the network is a duplicate and adds nothing. Then a free end lying within
// kJoinRadii of the wider radius of another polyline (segmentation tools leave curve ends a few
// millimetres short of the vessel they branch from or continue) is joined to it by a straight
// bridge to its nearest point there, and so is one whose own axis, extended by kReachRadii of its
// radius, enters another polyline's lumen (a branch stopping short of its parent's wall), there.
//
// Polylines with their topology given (SWC: every branching sample is a node) skip that step.
// Both then go through the same clean-up: repeated points removed, a branch from a junction to a
// free end shorter than kStubRadii of the junction's radius (the widest end there) pruned (its
// tip lies inside the vessel it leaves; a surface skeleton leaves such stubs where the flow
// collapsed), branches shorter than
// kContractRadii between two junctions contracted into one junction (the mesher needs room
// between junctions), chains through nodes with exactly two branches joined into one segment, a
// branch that returns to its own start split in two. Each connected piece is then oriented from
// its widest free end (or, without free ends, from a node on a cycle) by a depth-first walk:
// branches point away from the root, branches closing a cycle point back up it, so every junction
// has a segment ending there and one starting there, as HCLM's parent/child relation needs.
// The widest free end is a guess at the inlet that fails on a closed surface with an aneurysm (the
// sac's end is the widest): Orient names the inlet (the free end nearest a point roots its piece)
// and the sac (the blind segment nearest a point is named "aneurysm", which sim/flow closes).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/vessel_model.hpp"

namespace cathbox::vessel_import {

constexpr double kOverlapRadii = 0.25;  // a point this near the network (in its radii) lies on it
constexpr double kSnapRadii = 1.0;      // attaching this near a node (along the network) joins the node
constexpr double kContractRadii = 1.0;  // a branch this short between two junctions is contracted
constexpr double kJoinRadii = 2.0;      // a free end this near another polyline (in the wider radius) joins it
constexpr double kReachRadii = 2.0;     // ... or its axis extended this far (in its radius) entering a lumen
constexpr double kStubRadii = 1.0;      // a free-ended branch this short from a junction is pruned

struct Polyline {
  std::vector<vessel::CenterlinePoint> points;  // mm
  std::string name;                             // becomes the segment's name
  std::string where;                            // for messages: "cell 3", "curve 'Centerline curve (1)'"
};

// A polyline between two given nodes (explicit topology).
struct Branch {
  Polyline line;
  std::size_t from = 0;  // node ids, shared between branches that meet
  std::size_t to = 0;
};

struct NetworkStats {
  std::size_t polylines = 0;         // polylines given
  std::size_t overlapping = 0;       // that shared a run of points with the network
  std::size_t shared_points = 0;     // points dropped as shared
  std::size_t duplicates = 0;        // polylines lying entirely on the network
  std::size_t contracted = 0;        // short branches between junctions contracted
  std::size_t stubs = 0;             // free-ended stubs at junctions pruned
  double longest_stub_mm = 0.0;      // the longest of those
  std::size_t joined = 0;            // two-branch nodes joined through
  std::size_t ends_joined = 0;       // free ends bridged to a nearby polyline
  double widest_join_gap_mm = 0.0;   // the longest of those bridges
  std::size_t junctions = 0;
  std::size_t free_ends = 0;
  std::size_t components = 0;
  std::size_t cycles = 0;
};

// Points (mm, the network's frame) naming the inlet and an aneurysm sac; unset: the default above.
// A sac needs the inlet named too (kSacNeedsInlet).
struct Orient {
  std::optional<glm::dvec3> inlet_mm;  // the free end nearest it is its piece's root
  std::optional<glm::dvec3> sac_mm;    // the segment nearest it must end blind: named kSacName
};

// The error for a sac without an inlet: the default root, the widest free end, is on an aneurysm
// surface the sac's own end, which turns the entry into a blind outlet that passes as the sac.
inline constexpr const char* kSacNeedsInlet =
    "--sac: needs --inlet (without it the inlet is the widest free end, on an aneurysm surface the sac's own end)";

inline constexpr const char* kSacName = "aneurysm";  // sim/flow's is_sac_name closes such a blind end

struct NetworkBuild {
  vessel::VesselModel model;  // segment ids 1..n, the root's first segment first
  NetworkStats stats;
  std::string oriented;       // with Orient: what the points chose ("inlet: segment 1's start, 0.4 mm from the point")
  std::string error;          // empty on success; a bad Orient point's error starts "--inlet: " / "--sac: "
  [[nodiscard]] bool ok() const { return error.empty(); }
};

// Polylines given by geometry, in the order given (overlap is with the earlier ones).
[[nodiscard]] NetworkBuild build_network(const std::vector<Polyline>& polylines, const Orient& orient = {});

// Branches with their nodes given; node ids need not be dense.
[[nodiscard]] NetworkBuild build_network(const std::vector<Branch>& branches, const Orient& orient = {});

}  // namespace cathbox::vessel_import
