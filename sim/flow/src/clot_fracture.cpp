#include "flow/clot_fracture.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "lumen.hpp"

namespace cathbox::flow {

double clot_tensile_modulus_Pa(const ClotComposition& c) { return 1000.0 * clot_et75_kPa(c) / kTensileFromEt75; }

double wall_shear_Pa(const FlowNetwork& network, const CenterlinePosition& at) {
  const vessel::Segment& s = network.model().segments[at.segment];
  const double r_m = 1e-3 * radius_at_mm(s, point_arcs_mm(s), at.arc_mm);
  const double q_m3_s = 1e-9 * std::abs(network.segments()[at.segment].flow_mm3_s);
  const double mu_Pa_s = 1e-3 * network.settings().viscosity_mPa_s;
  return 4.0 * mu_Pa_s * q_m3_s / (std::numbers::pi * r_m * r_m * r_m);
}

double critical_crack_mm(const ClotComposition& c, double shear_Pa) {
  if (!(shear_Pa > 0.0)) return std::numeric_limits<double>::infinity();
  return 1e3 * kClotToughness_J_m2 * clot_tensile_modulus_Pa(c) / (std::numbers::pi * shear_Pa * shear_Pa);
}

std::vector<Fragment> fragments_in_flow(const Fragment& whole, double shear_Pa) {
  const double a_c = critical_crack_mm(whole.composition, shear_Pa);
  if (a_c >= std::max(whole.diameter_mm, whole.length_mm)) return {whole};
  const auto n = static_cast<std::size_t>(std::ceil(whole.length_mm / a_c));
  Fragment piece = whole;
  piece.length_mm = whole.length_mm / static_cast<double>(n);
  return std::vector<Fragment>(std::max<std::size_t>(n, 1), piece);
}

}  // namespace cathbox::flow
