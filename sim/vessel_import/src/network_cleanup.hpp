#pragma once
// The builder's steps on the network before orientation (network_builder.hpp describes them).
#include "network_graph.hpp"

namespace cathbox::vessel_import::detail {

// Free ends within kJoinRadii of another polyline are bridged to their nearest point there, and
// ends whose extended axis (kReachRadii of their radius) enters another polyline's lumen to the
// place it enters.
void join_near_ends(Graph& g, NetworkStats& stats);

// Branches that collapsed to a point merge their two nodes.
void merge_collapsed(Graph& g);

// Free-ended branches shorter than kStubRadii of their junction's radius: pruned.
void prune_stubs(Graph& g, NetworkStats& stats);

// Short branches between two junctions (kContractRadii): contracted into one junction at their middle.
void contract_short_branches(Graph& g, NetworkStats& stats);

// A branch from a node back to itself: split in two at its middle point.
void split_self_loops(Graph& g);

// Chains through nodes with exactly two branch ends (of two different branches): one segment.
// Then branches left without length are dropped.
void join_chains(Graph& g, NetworkStats& stats);

}  // namespace cathbox::vessel_import::detail
