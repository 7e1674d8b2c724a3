// The stick spring of a tool's friction in the lumen of the catheter round it (SheathFriction's
// anchor, its twist spring that times the inner radius squared): the axial compliance of the two
// shafts between the hands and the friction they share.
#pragma once

#include <algorithm>

#include "tool/rod.hpp"

namespace cathbox::tool {

// The hands hold both tools at the catheter's hub. The catheter's shaft runs from there to the
// entry point (its length less its depth past the entry) and on to the middle of the lumen the
// inner tool lies in (half the covered depth), the inner tool's shaft alongside it; the lumen's
// friction holds the two in series, each EA / L, EA the same the rods stretch with
// (ToolSpec::axial_stiffness_N). Sticking, the relative slide of the two hands is taken up by
// those shafts stretching and compressing, not by a contact's penalty: the bundled microcatheter
// (1,500 mm, 135 mm past the entry) over its wire, both at the default 5,000 N, 1.75 N/mm, where
// the stick spring's 2e4 mN/mm (RodSettings::stick_stiffness_mN_per_mm) turned the wire's lumen
// friction from +341 to -312 mN at 100 mN a tick as the microcatheter started over it at 5 mm/s
// (docs/sim-tool/convergence.md, "The lumen's stick spring is the shafts' axial compliance").
inline double sheath_anchor_mN_per_mm(const Rod& inner, double inner_depth_mm, const Rod& outer, double outer_depth_mm) {
  const double covered_mm = std::clamp(std::min(inner_depth_mm, outer_depth_mm), 0.0, outer.length_mm());
  const double shaft_mm = std::max(outer.length_mm() - outer_depth_mm, 0.0) + 0.5 * covered_mm;
  const double compliance_mm_per_N =
      shaft_mm * (1.0 / inner.spec().axial_stiffness_N + 1.0 / outer.spec().axial_stiffness_N);
  return 1e3 / std::max(compliance_mm_per_N, 1e-9);  // N/mm -> mN/mm
}

}  // namespace cathbox::tool
