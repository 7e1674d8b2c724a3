#include "tool/compliant_contact.hpp"

#include <algorithm>

#include "tool/simulator.hpp"

namespace cathbox::tool {

CompliantContact compliant_contact(const WallShell& shell) {
  return CompliantContact{shell.ring_load_stiffness_mN_per_mm(), kMaxHoopStrain * shell.radius_mm(),
                          patch_shear_stiffness_mN_per_mm2(shell.wall())};
}

void use_compliant_contact(Simulator& sim, const CompliantContact& contact) {
  for (std::size_t t = 0; t < sim.tool_count(); ++t) {
    if (sim.rod(t).spec().kind == ToolKind::kCoil) continue;
    double r_min = 1e9;
    for (const ToolSection& s : sim.rod(t).spec().sections) r_min = std::min(r_min, 0.5 * s.outer_diameter_mm);
    RodSettings& s = sim.rod_settings(t);
    s.contact_stiffness_mN_per_mm = contact.stiffness_mN_per_mm;
    s.wall_layer_mm = contact.max_displacement_mm;
    s.wall_stiffening = kCollagenStiffening;
    s.wall_shear_mN_per_mm2 = contact.shear_mN_per_mm2;
    s.max_penetration_ratio = std::max(s.max_penetration_ratio, kHardLimitLayers * contact.max_displacement_mm / r_min);
  }
}

}  // namespace cathbox::tool
