#pragma once
// Closest points of two segments, in double: the tool's edges against each other (coil loops),
// and the capsule queries against triangle edges.
#include <glm/vec3.hpp>

namespace cathbox::collision {

struct SegmentPair {
  double s = 0.0;  // parameter on the first segment, [0, 1]
  double t = 0.0;  // parameter on the second segment, [0, 1]
  double distance_sq = 0.0;
};

// Closest points of segments p0-p1 and q0-q1 (either may be a point).
[[nodiscard]] SegmentPair closest_segment_segment(const glm::dvec3& p0, const glm::dvec3& p1,
                                                  const glm::dvec3& q0, const glm::dvec3& q1);

}  // namespace cathbox::collision
