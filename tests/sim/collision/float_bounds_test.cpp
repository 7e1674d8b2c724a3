// The float lane kernels only prune, so they must never overstate a triangle's distance by more
// than the slack the queries allow for (float_bounds.hpp), nor understate the upper bracket by
// more. Checked here against exact double distances with half that slack, over triangles of
// every size from 10 um to 20 mm placed anywhere in a 600 mm box (slivers included), and query
// points from on the surface to 50 mm away.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>

#include <gtest/gtest.h>
#include <glm/geometric.hpp>

#include "float_bounds.hpp"
#include "kernels.hpp"
#include "triangle_block.hpp"
#include "triangle_geometry.hpp"

namespace cathbox::collision::detail {
namespace {

glm::dvec3 as_float(const glm::dvec3& p) {
  return {static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z)};
}

glm::dvec3 unit(std::mt19937& rng) {
  std::normal_distribution<double> g(0.0, 1.0);
  return glm::normalize(glm::dvec3{g(rng), g(rng), g(rng)});
}

struct Worst {
  double lower = -1.0;  // largest (float lower bound - exact) / slack
  double upper = -1.0;  // largest (exact - float upper bound) / slack
};

Worst measure(int triangles, bool slivers, std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> where(-300.0, 300.0);
  std::uniform_real_distribution<double> u01(0.0, 1.0);
  const double sizes[] = {0.01, 0.1, 1.0, 5.0, 20.0};
  const double reaches[] = {0.0, 1e-4, 1e-2, 0.5, 2.0, 50.0};
  Worst worst;
  for (int t = 0; t < triangles; ++t) {
    const double size = sizes[static_cast<std::size_t>(t) % 5];
    const glm::dvec3 centre{where(rng), where(rng), where(rng)};
    const glm::dvec3 a = as_float(centre + size * unit(rng));
    glm::dvec3 b = as_float(centre + size * unit(rng));
    glm::dvec3 c = as_float(centre + size * unit(rng));
    if (slivers && t % 3 == 0) c = as_float(a + u01(rng) * (b - a) + 1e-5 * size * unit(rng));
    const glm::dvec3 cross = glm::cross(b - a, c - a);
    const double len = glm::length(cross);
    if (!(len > 0.0)) continue;
    TriangleBlock block{};
    set_triangle_lane(block, 0, a, b, c, cross / len, 0);
    for (int lane = 1; lane < 4; ++lane) set_empty_triangle_lane(block, lane);
    // The smallest scale a mesh holding this triangle can have: the worst case for the slack.
    const double scale = std::max({std::abs(a.x), std::abs(b.x), std::abs(c.x)}) +
                         std::max({std::abs(a.y), std::abs(b.y), std::abs(c.y)}) +
                         std::max({std::abs(a.z), std::abs(b.z), std::abs(c.z)});
    for (double reach : reaches) {
      for (int q = 0; q < 4; ++q) {
        double w0 = u01(rng), w1 = u01(rng);
        if (w0 + w1 > 1.0) {
          w0 = 1.0 - w0;
          w1 = 1.0 - w1;
        }
        // Beside the triangle, above its edges and corners, and straight above it.
        const glm::dvec3 foot = q == 3 ? a : a + (1.3 * w0 - 0.15) * (b - a) + (1.3 * w1 - 0.15) * (c - a);
        const glm::dvec3 p = foot + reach * (q % 2 == 0 ? unit(rng) : cross / len);
        const double exact = std::sqrt(point_triangle_distance_sq(p, a, b, c));
        const PointLanes lanes = splat_point(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
        const DistanceBracket bracket = triangle_distance_sq(block, lanes);
        float lo[4];
        float hi[4];
        std::memcpy(lo, &bracket.lower, sizeof lo);
        std::memcpy(hi, &bracket.upper, sizeof hi);
        const double slack = static_cast<double>(slack_for(scale, p));
        worst.lower = std::max(worst.lower, (std::sqrt(std::max(0.0, static_cast<double>(lo[0]))) - exact) / slack);
        worst.upper = std::max(worst.upper, (exact - std::sqrt(static_cast<double>(hi[0]))) / slack);
      }
    }
  }
  return worst;
}

TEST(FloatBounds, TriangleBracketsStayWithinHalfTheSlack) {
  const Worst w = measure(20000, false, 3);
  std::printf("worst float error / slack: lower %.3f, upper %.3f\n", w.lower, w.upper);
  EXPECT_LE(w.lower, 0.5);
  EXPECT_LE(w.upper, 0.5);
}

TEST(FloatBounds, SliversKeepALowerBound) {
  // Slivers have no dual basis, so their lower bound is 0 and only the upper bracket is real.
  const Worst w = measure(6000, true, 5);
  EXPECT_LE(w.lower, 0.5);
  EXPECT_LE(w.upper, 0.5);
}

}  // namespace
}  // namespace cathbox::collision::detail
