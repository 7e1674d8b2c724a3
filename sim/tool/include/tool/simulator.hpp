#pragma once
// The tools in the vessel: one or two elastic rods (a guidewire alone, a catheter alone, or a
// guidewire inside a catheter), driven at the entry by insertion and rotation, stepped in
// virtual time. The caller drives time (one step() per haptic tick) and owns the wall.
//
// Coaxial tools follow the composite model of Lenoir, Cotin, Duriez, Neumann, "Interactive
// physically-based simulation of catheter and guidewire", Computers & Graphics 30(3), 2006:
// where the wire is inside the catheter, the two bend as one rod (the catheter carries the sum
// of their bending stiffnesses) and the wire follows the catheter's centreline; the part of
// the wire beyond the catheter tip is its own rod clamped at that tip, and a catheter advanced
// over the wire is predicted along the wire's path.
#include <cstdint>
#include <span>
#include <string_view>
#include <vector>

#include "tool/rod.hpp"
#include "tool/snapshot.hpp"
#include "tool/wall_model.hpp"

namespace cathbox::tool {

struct Entry {
  glm::dvec3 point_mm{0.0};
  glm::dvec3 direction{0.0, 0.0, 1.0};
};

class Simulator {
 public:
  // `wall` must outlive the simulator. Inner tools name their outer tool in ToolSpec::inside.
  Simulator(const WallModel& wall, std::span<const ToolSpec> tools, const Entry& entry,
            const RodSettings& settings = {});

  [[nodiscard]] std::size_t tool_count() const { return rods_.size(); }
  [[nodiscard]] std::size_t find_tool(std::string_view name) const;  // tool_count() if none
  void select(std::size_t tool);
  [[nodiscard]] std::size_t active_tool() const { return active_; }

  // Box input for one tool (the active one on a real box).
  void set_insertion(std::size_t tool, double insertion_mm);
  void set_rotation(std::size_t tool, double rotation_rad);
  [[nodiscard]] double insertion_mm(std::size_t tool) const { return insertion_[tool]; }
  [[nodiscard]] double rotation_rad(std::size_t tool) const { return rotation_[tool]; }

  // Advances the simulation by dt seconds (1 ms at haptic rate).
  void step(double dt_s = 1e-3);

  [[nodiscard]] double time_s() const { return time_s_; }
  [[nodiscard]] const Rod& rod(std::size_t tool) const { return rods_[tool]; }
  [[nodiscard]] std::int32_t tip_segment(std::size_t tool) const { return tip_segment_[tool]; }
  [[nodiscard]] double hand_force_mN(std::size_t tool) const;
  [[nodiscard]] double hand_torque_mNmm(std::size_t tool) const;
  [[nodiscard]] ForceLaw force_law(std::size_t tool) const;
  [[nodiscard]] TipPose tip(std::size_t tool) const { return rods_[tool].tip(); }
  // Inserted node positions of a tool, entry to tip, the part inside an outer tool included.
  void inserted_positions(std::size_t tool, std::vector<glm::dvec3>& out) const;

  void copy_snapshot(Snapshot& out) const;

 private:
  void step_inner(std::size_t tool, double dt_s);
  void update_composite(std::size_t outer);

  const WallModel& wall_;
  Entry entry_;
  std::vector<Rod> rods_;
  std::vector<std::size_t> outer_of_;  // index of the outer tool, or tool_count() if none
  std::vector<std::size_t> order_;     // outer tools first
  std::vector<double> insertion_, rotation_, stepped_insertion_;
  std::vector<std::int32_t> tip_segment_;
  std::vector<WallHint> tip_hint_;
  std::vector<double> extra_ei_;       // scratch for the composite stiffness
  std::size_t active_ = 0;
  double time_s_ = 0.0;
  std::uint64_t steps_ = 0;
};

}  // namespace cathbox::tool
