#pragma once
// A junction patch's triangles paired into quads: across the edges that join two different
// rings, an exact perfect matching where the band triangles form chains between triple
// triangles (the longest removed edges win), then closed chains, then greedily.
#include <array>
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::vessel::detail {

// A directed edge a -> b as one key.
[[nodiscard]] inline std::uint64_t directed_edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// Faces (quads, and triangles left unpaired) from `tris` (point indices, ring r point m ->
// r * ring_points + m); `points` give the edge lengths.
[[nodiscard]] std::vector<std::vector<int>> pair_into_quads(const std::vector<std::array<int, 3>>& tris,
                                                            const std::vector<glm::dvec3>& points, int ring_points);

}  // namespace cathbox::vessel::detail
