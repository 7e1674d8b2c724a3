#pragma once
// A 64-bit hash (XXH3) of the simulation state after a step: every tool's inserted node
// positions and material frames, insertion, rotation, hand force and torque, tip segment and
// contacts (node and normal force), bit for bit. Two runs that consumed the same inputs give
// the same hashes; the record stores one every `hash_every` ticks and a replay compares them.
#include <cstdint>

#include "tool/snapshot.hpp"

namespace cathbox::session {

[[nodiscard]] std::uint64_t state_hash(const tool::Snapshot& snapshot);

}  // namespace cathbox::session
