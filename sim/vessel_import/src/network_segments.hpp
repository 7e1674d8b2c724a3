#pragma once
// From the cleaned network to HCLM segments: each piece oriented depth-first from its root.
#include <cstddef>

#include <glm/vec3.hpp>

#include "network_graph.hpp"

namespace cathbox::vessel_import::detail {

// The free end nearest `p` (kNone: no free end) and its distance.
[[nodiscard]] std::size_t nearest_free_end(const Graph& g, const glm::dvec3& p, double& distance);

// Orients each piece from its root (`inlet` for the piece holding it, else its widest free end,
// or a node on a cycle) and appends its segments to out.model in discovery order, with parents
// and children; counts junctions, free ends, components and cycles into `stats`. False (out.error
// set) for a junction no segment ends or starts at.
bool oriented_segments(Graph& g, std::size_t inlet, NetworkBuild& out, NetworkStats& stats);

}  // namespace cathbox::vessel_import::detail
