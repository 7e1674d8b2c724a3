#pragma once
// What a guidewire or a catheter is made of: sections along its length (proximal to distal),
// each with an outer diameter, bending and torsional stiffness and an optional pre-curve
// (J-tip, angled tip), plus the wall friction and the node spacing of its discretisation.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

namespace cathbox::tool {

enum class ToolKind : std::uint8_t { kGuidewire = 0, kCatheter = 1 };

struct ToolSection {
  double length_mm = 0.0;
  double outer_diameter_mm = 0.36;
  double bending_stiffness_Nmm2 = 40.0;    // EI
  double torsion_stiffness_Nmm2 = 30.0;    // GJ
  double curve_deg = 0.0;                  // pre-curve: total bend of this section at rest
};

struct ToolSpec {
  std::string name = "guidewire";
  ToolKind kind = ToolKind::kGuidewire;
  std::vector<ToolSection> sections;       // proximal first; the last one holds the tip
  double friction = 0.1;                   // Coulomb coefficient against the wall (and the outer tool)
  double inner_diameter_mm = 0.0;          // catheters: lumen diameter (0 for a guidewire)
  double axial_stiffness_N = 5000.0;       // EA; large, the tool is nearly inextensible
  double drag_mN_s_per_mm2 = 0.01;         // viscous drag per mm of tool per mm/s (blood, sheath)
  double max_spacing_mm = 2.0;             // node spacing along the shaft
  double tip_spacing_mm = 0.5;             // node spacing over the distal tip_zone_mm
  double tip_zone_mm = 10.0;
  std::string inside;                      // name of the tool this one runs inside (coaxial), or ""

  [[nodiscard]] double length_mm() const {
    double total = 0.0;
    for (const ToolSection& s : sections) total += s.length_mm;
    return total;
  }
};

// The limits a tool must keep (the case file checks them statement by statement).
struct ToolLimits {
  static constexpr std::size_t kMaxTools = 4;
  static constexpr std::size_t kMaxSections = 64;
  static constexpr double kMaxLength_mm = 4000.0;
  static constexpr double kMaxNodes = 6000.0;
  static constexpr double kMaxDiameter_mm = 20.0;
  static constexpr double kMaxStiffness_Nmm2 = 1e6;
  static constexpr double kMaxCurve_deg = 360.0;
  static constexpr double kMaxFriction = 2.0;
  static constexpr double kMaxSpacing_mm = 2.0;
  static constexpr double kMinTipSpacing_mm = 0.1;
  static constexpr double kMaxTipZone_mm = 500.0;
  static constexpr double kMaxDrag = 10.0;
  static constexpr double kMinAxialStiffness_N = 10.0;
  static constexpr double kMaxAxialStiffness_N = 1e6;
};

// Checks a set of tools as a simulator takes them (every value in range, names unique, coaxial
// tools inside a known catheter they fit in): "" when fine, else one line naming the tool and
// the value. For tools that did not come from a case file (a session record).
[[nodiscard]] std::string check_tools(std::span<const ToolSpec> tools);

}  // namespace cathbox::tool
