#pragma once
// What a guidewire or a catheter is made of: sections along its length (proximal to distal),
// each with an outer diameter, bending and torsional stiffness and an optional pre-curve
// (J-tip, angled tip), plus the wall friction and the node spacing of its discretisation.
#include <cstdint>
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

}  // namespace cathbox::tool
