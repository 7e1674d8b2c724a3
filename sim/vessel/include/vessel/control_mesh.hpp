#pragma once
// The quad-dominant control mesh built from the central axis model (thesis 3.2.3.2), before
// subdivision: rings of M points around the smoothed centerline, quads between successive
// rings of a segment (connection rule 1), junction patches between the rings that meet at a
// junction, and caps on free ends.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/surface_mesh.hpp"

namespace cathbox::vessel {

// One cross-section ring. The ring's points are
//   center + control_radius * (cos(2 pi m / M) * normal + sin(2 pi m / M) * binormal),
// m = 0..M-1, stored at vertices first_vertex + m; (normal, binormal, tangent) is right-handed.
struct Ring {
  std::uint32_t segment = 0;       // index into VesselModel::segments
  glm::dvec3 center_mm{0.0};
  glm::dvec3 tangent{0.0, 0.0, 1.0};  // along the segment, first point -> last point
  glm::dvec3 normal{1.0, 0.0, 0.0};
  glm::dvec3 binormal{0.0, 1.0, 0.0};
  double radius_mm = 0.0;          // the (smoothed) model radius here
  double control_radius_mm = 0.0;  // the ring's radius in the control mesh
  double arc_mm = 0.0;             // arc length along the segment's smoothed centerline
  std::uint32_t first_vertex = 0;
};

// A junction whose rings' own hull could not give its patch, meshed by the spherical-hull
// fallback (src/junction_patch.hpp): which one, and why the hull could not.
struct JunctionFallback {
  std::uint32_t junction = 0;  // index in VesselGraph::junctions()
  std::string what;            // "junction 3 (segments 5 6 7): branches overlap (...)"
};

struct ControlMesh {
  int ring_points = 0;                       // M
  std::vector<glm::dvec3> positions_mm;
  std::vector<int> face_sizes;               // vertices per face (3, 4 or M for caps)
  std::vector<int> face_vertices;            // concatenated, counter-clockwise from outside
  std::vector<FaceRegion> face_regions;      // one per face
  std::vector<Ring> rings;                   // the rings of each segment, in segment order
  std::vector<std::uint32_t> segment_first_ring;  // per segment: index of its first ring (+ end sentinel)
  std::vector<JunctionFallback> fallback_junctions;  // junctions meshed by the fallback, in order

  [[nodiscard]] std::size_t face_count() const { return face_sizes.size(); }
  [[nodiscard]] std::size_t vertex_count() const { return positions_mm.size(); }
};

}  // namespace cathbox::vessel
