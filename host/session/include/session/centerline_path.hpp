#pragma once
// The way through a vessel network along its centerline, from an entry point to a target (a
// segment and a fraction of its length): what the scripted hand follows. Segments meet at
// junctions: a segment's start joins its parents' ends (and its siblings' starts), its end its
// children's starts (and, at a confluence, the other parents' ends). The path may run down a
// segment or back up it (a femoral approach climbs the descending aorta against its
// direction), and is the shortest such way by length (Dijkstra over segment ends).
#include <cstddef>
#include <optional>
#include <vector>

#include <glm/vec3.hpp>

namespace cathbox::session {

struct PathSegment {
  std::vector<glm::vec3> points_mm;  // proximal to distal
  std::vector<std::size_t> parents;  // indices into the segment list
  std::vector<std::size_t> children;
};

struct PathPoint {
  std::size_t segment = 0;
  double fraction = 0.0;  // of the segment's length, 0 at its start
};

class CenterlinePath {
 public:
  // The centerline point nearest to p.
  [[nodiscard]] static PathPoint nearest(const std::vector<PathSegment>& segments, const glm::vec3& p);
  // The point at a fraction of a segment's length.
  [[nodiscard]] static glm::vec3 point_at(const PathSegment& segment, double fraction);
  // The polyline from `from` to `to`; empty when the target cannot be reached. With
  // `segments_out`, also the indices of the segments it runs along, in order.
  [[nodiscard]] static std::vector<glm::vec3> between(const std::vector<PathSegment>& segments,
                                                      const PathPoint& from, const PathPoint& to,
                                                      std::vector<std::size_t>* segments_out = nullptr);
  // Length of a polyline.
  [[nodiscard]] static double length_mm(const std::vector<glm::vec3>& polyline);
  // The end of the leaf segment farthest (along the network) from `from`: the destination when
  // a case names no target.
  [[nodiscard]] static std::optional<PathPoint> farthest_leaf(const std::vector<PathSegment>& segments,
                                                              const PathPoint& from);
};

}  // namespace cathbox::session
