#pragma once
// The environments' "state" observation in one pass over the session's state (instead of a
// dozen calls and numpy's concatenate/clip/astype after each step, ~50 µs of a DualDevice step
// at a 6 ms tick, most of it with the caches cold after the solve):
//
//   per tool t: points_from_tip(t, count, spacing_mm) (count × 3 mm), the tip's unit direction
//               (3), insertion mm, rotation rad;
//   then the target (3 mm) and the last action (tools × 2);
//
// every value clipped to [-limit, limit] in double and then rounded to float, as
// numpy.clip(..., -limit, limit).astype(numpy.float32) gives it (NaN stays NaN).
//
//   std::vector<float> obs(python::state_observation_size(snap.tools.size(), 16));
//   python::state_observation(snap, 16, 5.0, target_mm, last_action, 1e4, obs);
#include <cstddef>
#include <span>

#include <glm/vec3.hpp>

#include "tool/snapshot.hpp"

namespace cathbox::python {

[[nodiscard]] std::size_t state_observation_size(std::size_t tools, std::size_t count);

// tools: the first `tools` of snap.tools (the case's); last_action holds tools × 2 values;
// out holds state_observation_size(tools, count) values.
void state_observation(const tool::Snapshot& snap, std::size_t tools, std::size_t count, double spacing_mm,
                       const glm::dvec3& target_mm, std::span<const double> last_action, double limit,
                       std::span<float> out);

}  // namespace cathbox::python
