#pragma once
// A copy of the simulation state for the renderer and the trainer: node positions and frames,
// tip, contacts, hand force. Simulator::copy_snapshot() refills one in place; after the first
// copy it reuses the vectors' capacity, so copying at display rate does not allocate.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "tool/force_law.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool {

struct ToolSnapshot {
  std::string name;
  ToolKind kind = ToolKind::kGuidewire;
  double insertion_mm = 0.0;
  double rotation_rad = 0.0;
  std::vector<glm::dvec3> positions_mm;  // inserted nodes from the entry to the tip
  std::vector<glm::dvec3> tangents;      // unit, distal, one per node
  std::vector<glm::dvec3> normals;       // material director m1, one per node
  std::vector<float> radii_mm;           // outer radius, one per node
  TipPose tip;
  std::int32_t tip_segment = -1;         // vessel segment holding the tip (-1: none)
  std::vector<RodContact> contacts;
  double hand_force_mN = 0.0;
  double hand_torque_mNmm = 0.0;
  ForceLaw force_law;
  bool detached = false;                 // a released coil (no hand, no insertion)
  double balloon_pressure_atm = 0.0;     // balloon catheters
  double balloon_diameter_mm = 0.0;      // unconstrained diameter at that pressure
};

struct Snapshot {
  double time_s = 0.0;
  std::uint64_t step = 0;
  std::size_t active_tool = 0;
  std::vector<ToolSnapshot> tools;       // the tools in case order, then the released coils
};

}  // namespace cathbox::tool
