#pragma once
// The control mesh builder's steps (control_mesh_builder.cpp: the run and the junctions' trims;
// control_mesh_rings.cpp: rings and their frames; control_mesh_faces.cpp: vertices and faces).
// Private to sim/vessel.
#include <cstddef>
#include <cstdint>
#include <initializer_list>
#include <numbers>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "centerline_polyline.hpp"
#include "vessel/control_mesh_builder.hpp"

namespace cathbox::vessel::detail {


class ControlMeshBuilder {
 public:
  ControlMeshBuilder(const VesselModel& model, const VesselGraph& graph, const MeshOptions& options)
      : model_(model), graph_(graph), options_(options), m_(options.ring_points) {}

  ControlMeshResult run();

 private:
  [[nodiscard]] double end_arc(const SegmentEnd& e, double trim) const;

  // Two passes: every junction first keeps to its share of each segment; those still
  // overlapping may then use what the segment's other end left over.
  void compute_trims();

  // Moves the junction's rings out along their segments until each ring lies behind the plane
  // of every other ring there. Returns false if a segment ran out of length first.
  bool trim_junction(const Junction& junction, bool relaxed);

  // How far the junction may trim segment end e: its share of the segment, or (relaxed) what
  // the segment's other end left over.
  [[nodiscard]] double trim_limit(const Junction& junction, const SegmentEnd& e, bool relaxed) const;

  // Whether some other ring j reaches in front of ring i's plane (past the margin).
  [[nodiscard]] bool ring_in_front(const std::vector<Sample>& at, const std::vector<glm::dvec3>& out_normal, std::size_t i) const;

  // Sizes known up front (junction patches estimated by M faces per incident ring), so the
  // mesh arrays are allocated once instead of growing.
  void reserve_mesh();

  void place_rings();

  // The arc positions of a segment's rings between the trimmed ends a and b (see RingPlacement).
  void ring_arcs(const Polyline& pl, double a, double b, std::vector<double>& arcs) const;

  // Along the segment, Catmull-Clark converges to the cubic B-spline of the ring sequence, whose
  // value at ring j is (c[j-1] + 4 c[j] + c[j+1]) / 6: bends would cut inward and radius changes
  // flatten. The inner rings' centres and radii are solved for exactly (a tridiagonal system,
  // end rings fixed) so that these averages hit the targets.
  void correct_axial_shrink(std::size_t begin, std::size_t end);

  [[nodiscard]] std::size_t end_ring(const SegmentEnd& e) const;

  // Sets the normals of segment s's rings, starting at the given end with `normal`.
  void propagate_segment(std::uint32_t s, bool from_end, const glm::dvec3& normal);

  void propagate_frames();

  std::uint32_t add_ring_vertices(const glm::dvec3& center, const glm::dvec3& normal, const glm::dvec3& binormal,
                                  double radius);

  void emit_vertices();

  void add_face(std::initializer_list<std::uint32_t> vertices, FaceRegion region);

  // Quads between ring a and the next ring b along the tangent (outward, counter-clockwise).
  void add_band(std::uint32_t a, std::uint32_t b, FaceRegion region);

  void emit_tubes();

  void emit_caps();

  std::string emit_junctions();

  const VesselModel& model_;
  const VesselGraph& graph_;
  const MeshOptions& options_;
  const int m_;
  double ratio_ = 1.0;
  std::vector<Polyline> polylines_;
  std::vector<double> trims_;
  std::vector<double> ring_cos_, ring_sin_;  // cos / sin(2 pi m / M)
  std::vector<glm::dvec3> target_c_, solved_c_;  // scratch of the axial correction
  std::vector<double> target_r_, solved_r_;
  ControlMesh mesh_;
};

}  // namespace cathbox::vessel::detail
