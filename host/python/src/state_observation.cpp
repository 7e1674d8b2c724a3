#include "python/state_observation.hpp"

#include <algorithm>
#include <cassert>
#include <vector>

#include "python/tip_points.hpp"

namespace cathbox::python {

std::size_t state_observation_size(std::size_t tools, std::size_t count) { return tools * (count * 3 + 3 + 2) + 3 + tools * 2; }

void state_observation(const tool::Snapshot& snap, std::size_t tools, std::size_t count, double spacing_mm,
                       const glm::dvec3& target_mm, std::span<const double> last_action, double limit,
                       std::span<float> out) {
  assert(tools <= snap.tools.size() && last_action.size() == 2 * tools && out.size() == state_observation_size(tools, count));
  std::size_t i = 0;
  // numpy.clip(x, -limit, limit).astype(float32): NaN passes through std::clamp unchanged too.
  const auto put = [&](double v) { out[i++] = static_cast<float>(std::clamp(v, -limit, limit)); };
  const auto put3 = [&](const glm::dvec3& v) {
    put(v.x);
    put(v.y);
    put(v.z);
  };
  std::vector<glm::dvec3> points(count);
  for (std::size_t t = 0; t < tools; ++t) {
    const tool::ToolSnapshot& s = snap.tools[t];
    points_from_tip(s.positions_mm, spacing_mm, points);
    for (const glm::dvec3& p : points) put3(p);
    put3(s.tip.direction);
    put(s.insertion_mm);
    put(s.rotation_rad);
  }
  put3(target_mm);
  for (const double a : last_action) put(a);
}

}  // namespace cathbox::python
