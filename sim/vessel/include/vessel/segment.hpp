#pragma once
// One vessel segment of the central axis model (HCLM `g` block): an ordered list of centerline
// points with the radius of the cross section at each point, plus its place in the network.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::vessel {

struct CenterlinePoint {
  glm::dvec3 pos_mm{0.0};
  double radius_mm = 0.0;
  friend bool operator==(const CenterlinePoint&, const CenterlinePoint&) = default;
};

struct Segment {
  std::int32_t id = 0;                 // `g` line: unique id
  std::string name;                    // `l` line (may be empty)
  double flow = 0.0;                   // `f` line: blood flow (unit as in the source data)
  std::vector<std::int32_t> parents;   // `p` line: ids of the parent segments
  std::vector<std::int32_t> children;  // `c` line: ids of the child segments
  std::vector<CenterlinePoint> points; // `v` lines, from the proximal to the distal end
  friend bool operator==(const Segment&, const Segment&) = default;
};

}  // namespace cathbox::vessel
