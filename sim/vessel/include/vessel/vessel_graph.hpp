#pragma once
// The topology of a vessel network: where segment ends meet. Every segment has two ends
// (start = first point, end = last point); a parent/child pair joins the parent's end to the
// child's start. Ends joined this way form one node. A node with two or more ends is a
// junction (continuation, bifurcation, trifurcation, confluence, ...), a node with one end is
// a free end. The graph may contain cycles (circle of Willis).
#include <cstdint>
#include <vector>

#include <glm/vec3.hpp>

#include "vessel/vessel_model.hpp"

namespace cathbox::vessel {

struct SegmentEnd {
  std::uint32_t segment = 0;  // index into VesselModel::segments
  bool at_end = false;        // false: the segment's first point, true: its last point
  friend bool operator==(const SegmentEnd&, const SegmentEnd&) = default;
};

struct Junction {
  std::vector<SegmentEnd> ends;  // the incident segment ends (>= 2)
  glm::dvec3 center_mm{0.0};     // mean of the incident end points
};

class VesselGraph {
 public:
  // The model must have passed validation (ids unique, lists consistent).
  explicit VesselGraph(const VesselModel& model);

  [[nodiscard]] const std::vector<Junction>& junctions() const { return junctions_; }
  [[nodiscard]] const std::vector<SegmentEnd>& free_ends() const { return free_ends_; }
  // Junction index of a segment end, or -1 when that end is free.
  [[nodiscard]] int junction_of(std::uint32_t segment, bool at_end) const {
    return end_junction_[2 * segment + (at_end ? 1 : 0)];
  }
  [[nodiscard]] int component_count() const { return components_; }
  // Independent cycles (first Betti number of the segment graph): segments - nodes + components.
  [[nodiscard]] int cycle_count() const { return cycles_; }
  // Euler characteristic of the closed vessel surface: 2 * components - 2 * cycles.
  [[nodiscard]] int surface_euler_characteristic() const { return 2 * components_ - 2 * cycles_; }

 private:
  std::vector<Junction> junctions_;
  std::vector<SegmentEnd> free_ends_;
  std::vector<int> end_junction_;
  int components_ = 0;
  int cycles_ = 0;
};

}  // namespace cathbox::vessel
