#pragma once
// Whether the blood flow tears a free clot (one stripped off a device, travelling) into pieces:
// Griffith's criterion for a crack opened by the shear traction of the flow on the clot's
// surface (the mechanism of thrombotic embolisation in Tutwiler et al., Sci Adv 2020, Fig. 1A).
// A crack of length a in a clot of tensile modulus E under a traction tau releases
// G = pi tau^2 a / E; it runs when G reaches the clot's toughness G_c = 7.6 +- 0.45 J/m^2
// (Tutwiler et al. 2020: human plasma fibrin clots). The tensile modulus is Et75 / 40 (Cahalane
// et al., Ann Biomed Eng 2023: high-strain compressive ~ 40 x tensile; clot_material.hpp). The
// traction is the wall shear of Poiseuille flow where the clot is, 4 mu |Q| / (pi r^3).
// At arterial shear (1-10 Pa) the critical crack is metres long: the flow does not break a clot,
// it carries it whole (devices fragment clots, the flow does not).
#include <vector>

#include "flow/centerline_locator.hpp"
#include "flow/clot_material.hpp"
#include "flow/embolus.hpp"
#include "flow/flow_network.hpp"

namespace cathbox::flow {

inline constexpr double kClotToughness_J_m2 = 7.6;  // Tutwiler et al., Sci Adv 2020: 7.6 +- 0.45
inline constexpr double kTensileFromEt75 = 40.0;    // Cahalane et al. 2023: Et75 ~ 40 x tensile modulus

// The clot's tensile modulus, Pa.
[[nodiscard]] double clot_tensile_modulus_Pa(const ClotComposition& c);
// The wall shear stress of the network's flow at a centreline position, Pa.
[[nodiscard]] double wall_shear_Pa(const FlowNetwork& network, const CenterlinePosition& at);
// The shortest crack the traction `shear_Pa` runs through a clot of composition `c`, mm
// (a_c = G_c E / (pi tau^2)); infinite without traction.
[[nodiscard]] double critical_crack_mm(const ClotComposition& c, double shear_Pa);
// What `whole` becomes in the flow where it is released: itself when no crack as long as its
// largest dimension runs; else cut along its length into equal pieces no longer than the
// critical crack (all released where it was).
[[nodiscard]] std::vector<Fragment> fragments_in_flow(const Fragment& whole, double shear_Pa);

}  // namespace cathbox::flow
