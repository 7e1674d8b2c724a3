#pragma once
// A 64-bit FNV-1a hash of a simulator's state, bit for bit: every tool's node positions, hand
// force and torque, and every released coil's nodes. Tests chain it over ticks or print it at
// the end of a run, to tell whether two runs of the same inputs gave the same state.
#include <cstdint>
#include <cstring>

#include "tool/simulator.hpp"

namespace cathbox::tool::testing {

inline constexpr std::uint64_t kFnvBasis = 0xcbf29ce484222325ull;

inline std::uint64_t state_fnv(const Simulator& sim, std::uint64_t h = kFnvBasis) {
  const auto add = [&h](double v) {
    unsigned char bytes[sizeof v];
    std::memcpy(bytes, &v, sizeof v);
    for (const unsigned char b : bytes) h = (h ^ b) * 0x100000001b3ull;
  };
  const auto add_nodes = [&add](const Rod& rod) {
    for (const glm::dvec3& p : rod.positions()) {
      add(p.x);
      add(p.y);
      add(p.z);
    }
  };
  for (std::size_t t = 0; t < sim.tool_count(); ++t) {
    add_nodes(sim.rod(t));
    add(sim.hand_force_mN(t));
    add(sim.hand_torque_mNmm(t));
  }
  for (std::size_t c = 0; c < sim.detached_count(); ++c) add_nodes(sim.detached(c));
  return h;
}

}  // namespace cathbox::tool::testing
