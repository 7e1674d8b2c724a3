#pragma once
// How far the float lane kernels (kernels.hpp) may be off, and the float thresholds that keep
// every triangle or box that can matter.
//
// Error of a float bound near query point p (to first order, u = 2^-24 the unit roundoff):
// rounding p to float moves it by at most u * |p|_1; the differences w = p - a and p - centre
// (|w| <= |p|_1 + scale, scale = the mesh's sum of largest absolute coordinates) and the three
// dot products with a rounded unit vector add at most about 10 u |w|; an edge parameter rounded
// by du moves the edge distance only to second order. So a bound is off by at most about
// 11 u (scale + |p|_1). The slack is 32 u (scale + |p|_1), about three times that; the tree's
// boxes are also grown by 16 * FLT_EPSILON * (scale + half extents) when stored in floats. The
// test float_bounds_test checks the triangle bounds against exact distances with half this slack.
#include <cfloat>
#include <cmath>
#include <limits>

#include <glm/vec3.hpp>

namespace cathbox::collision::detail {

// Bound on the float error of a distance bound near p (mm).
inline float slack_for(double scale_mm, const glm::dvec3& p) {
  return static_cast<float>(16.0 * FLT_EPSILON * (scale_mm + std::abs(p.x) + std::abs(p.y) + std::abs(p.z)));
}

// Float threshold on squared lower bounds that keeps everything within `dist` of the query.
inline float threshold_sq(double dist, float slack) {
  if (!(dist < 1e18)) return std::numeric_limits<float>::infinity();
  const double t = dist + static_cast<double>(slack);
  return static_cast<float>(t * t * (1.0 + 1e-6));
}

}  // namespace cathbox::collision::detail
