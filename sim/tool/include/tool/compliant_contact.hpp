#pragma once
// Tool-wall contact against a compliant arterial wall (a case's `wall TERRITORY RADIUS_MM`):
// a node pressed into the wall moves it by its own mechanics, so the contact force of a node
// pressing the wall by w is K w with K the wall's radial stiffness (WallShell: the stiffness to
// a load round one circumference of a tube of that radius, the stiffest a wall can be to a
// node's load) instead of the rigid wall's numerical penalty (RodSettings::
// contact_stiffness_mN_per_mm, 2e5 mN/mm). The wall gives K w up to a bounded layer, w =
// `kMaxHoopStrain` R, where collagen fibres, slack at physiological strain, are recruited and
// the wall stiffens by an order of magnitude (the nonlinear stiffening of arteries, e.g.
// Holzapfel, Gasser & Ogden, J Elasticity 61, 2000): past the layer a node meets
// `kCollagenStiffening` K (wall_penalty.hpp), in the step's energy, so the solve converges on
// the force the wall gives. The solver's hard limit on a node's penetration (a numerical guard,
// after the solve) is `kHardLimitLayers` layers. Friction's stick spring is the same tissue's
// shear stiffness under the node's patch (patch_shear_stiffness_mN_per_mm2, Mindlin). Coils keep
// their own contact settings (soft loops against the sac); tool-tool contact of non-coil tools
// takes the same normal stiffness. Valve anchors are not the wall's and keep
// the simulator's.
#include <cstddef>

#include "tool/arterial_wall.hpp"

namespace cathbox::tool {

class Simulator;

inline constexpr double kMaxHoopStrain = 0.25;
inline constexpr double kCollagenStiffening = 10.0;  // "an order of magnitude": an estimate
inline constexpr double kHardLimitLayers = 2.0;

struct CompliantContact {
  double stiffness_mN_per_mm = 0.0;  // per node
  double max_displacement_mm = 0.0;  // the bounded layer (then the wall stiffens)
  double shear_mN_per_mm2 = 0.0;     // friction's stick spring per mm of a node's radius
};

[[nodiscard]] CompliantContact compliant_contact(const WallShell& shell);

// Every non-coil tool of `sim` takes the compliant contact (call once, after construction).
// A case's `wall` line reaches it through scenario/case_wall.hpp.
void use_compliant_contact(Simulator& sim, const CompliantContact& contact);

}  // namespace cathbox::tool
