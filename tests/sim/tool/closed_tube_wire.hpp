#pragma once
// A uniform 0.014" wire (EI 40 N mm^2, frictionless) in a straight tube of radius 2 mm closed
// 200 mm on: the wire that buckles into Lubinski's helix past the closed end (Lubinski, Althouse
// & Logan, J. Petroleum Technology 14(6), 1962; helical_buckling_test.cpp derives the law).
// Shared by the helix's validation and the sub-stepped ticks' test (rod_substep_test.cpp).
#include "analytic_walls.hpp"
#include "tool/rod.hpp"

namespace cathbox::tool::testing {

inline constexpr double kHelixTubeRadius_mm = 2.0;
inline constexpr double kHelixWireDiameter_mm = 0.36;
inline constexpr double kHelixWireEi_Nmm2 = 40.0;  // the bundled 0.014" guidewire's shaft
inline constexpr double kHelixTubeEnd_mm = 200.0;
// The insertion at which the tip meets the closed end (the capsule's pole, a radius past its
// axis' end), and the wire's radial clearance in the tube.
inline constexpr double kHelixContact_mm = kHelixTubeEnd_mm + kHelixTubeRadius_mm - kHelixWireDiameter_mm / 2.0;
inline constexpr double kHelixClearance_mm = kHelixTubeRadius_mm - kHelixWireDiameter_mm / 2.0;

inline TubeNetworkWall closed_helix_tube() { return straight_tube(kHelixTubeRadius_mm, -10.0, kHelixTubeEnd_mm); }

// The wire, 600 mm, nodes every 1 mm, its entry at the origin along +z; frictionless unless told.
inline Rod closed_tube_wire(const RodSettings& settings = {}, double friction = 0.0) {
  ToolSpec spec;
  spec.name = "wire";
  spec.sections.push_back(ToolSection{600.0, kHelixWireDiameter_mm, kHelixWireEi_Nmm2, 31.0, 0.0});
  spec.friction = friction;
  spec.max_spacing_mm = 1.0;
  spec.tip_spacing_mm = 1.0;
  Rod rod(spec, settings);
  rod.set_entry({0, 0, 0}, {0, 0, 1});
  return rod;
}

// Lubinski's helix: the axial force, mN, of the wire pushed delta_mm past the closed end,
// F = 4 EI delta / (r^2 L).
inline double lubinski_helix_mN(double delta_mm) {
  return 4.0 * kHelixWireEi_Nmm2 * 1000.0 * delta_mm / (kHelixClearance_mm * kHelixClearance_mm * kHelixContact_mm);
}

}  // namespace cathbox::tool::testing
