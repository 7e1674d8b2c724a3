#include "python/tip_points.hpp"

#include <algorithm>

#include <glm/geometric.hpp>

namespace cathbox::python {

void points_from_tip(std::span<const glm::dvec3> nodes_mm, double spacing_mm, std::span<glm::dvec3> out) {
  if (nodes_mm.empty()) {
    std::fill(out.begin(), out.end(), glm::dvec3(0.0));
    return;
  }
  // Walk from the tip towards the entry: node i (counted back from the tip) at arc length s_i.
  std::size_t i = nodes_mm.size() - 1;  // the segment [i - 1, i] holds the arc length wanted
  double s_i = 0.0;                      // arc length of node i back from the tip
  for (std::size_t k = 0; k < out.size(); ++k) {
    const double want_mm = static_cast<double>(k) * spacing_mm;
    while (i > 0) {
      const double len = glm::distance(nodes_mm[i], nodes_mm[i - 1]);
      if (s_i + len >= want_mm && len > 0.0) {
        const double f = std::clamp((want_mm - s_i) / len, 0.0, 1.0);
        out[k] = nodes_mm[i] + f * (nodes_mm[i - 1] - nodes_mm[i]);
        break;
      }
      s_i += len;
      --i;
    }
    if (i == 0) out[k] = nodes_mm[0];
  }
}

}  // namespace cathbox::python
