#include "flow/xray_material.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::flow {
namespace {

// ---------------------------------------------------------------------------------------------
// Mass attenuation coefficients mu/rho (cm^2/g, coherent scattering included) at 40, 50 and
// 60 keV from Hubbell JH, Seltzer SM. Tables of X-Ray Mass Attenuation Coefficients and Mass
// Energy-Absorption Coefficients from 1 keV to 20 MeV for Elements Z = 1 to 92 and 48
// Additional Substances of Dosimetric Interest. NISTIR 5632, NIST 1995 (database 126,
// version 1.4, 2004): tables ComTab/tissue4, brain, bone; ElemTab z53 (I), z78 (Pt), z28 (Ni),
// z22 (Ti), z26 (Fe), z24 (Cr); air's mu_en/rho from ComTab/air. Mixtures by weight fractions.
//
// Effective energy: a neuro fluoroscopy beam of 70-90 kVp with 0.1-0.3 mm added copper
// filtration has a mean photon energy of roughly 45-55 keV (about 60 % of the kVp for such
// hardened spectra; e.g. Bushberg JT et al., The Essential Physics of Medical Imaging, 3rd ed.,
// ch. 6 and 9); 50 keV is used by default. Iodine's K edge (33.2 keV) lies below, so iodine
// attenuates ~55 times more than soft tissue per gram there.
// ---------------------------------------------------------------------------------------------
struct Row {
  double mu40, mu50, mu60;  // cm^2/g
  double density;           // g/cm^3
};

constexpr Row kSoftTissue{0.2609, 0.2223, 0.2025, 1.00};
constexpr Row kBrain{0.2702, 0.2275, 0.2058, 1.04};
constexpr Row kBone{0.6655, 0.4242, 0.3148, 1.92};
constexpr Row kIodine{22.10, 12.32, 7.579, 1.0};  // per g/cm^3 of iodine
constexpr Row kPlatinum{12.45, 6.954, 4.339, 21.45};
constexpr Row kNickel{4.600, 2.474, 1.512, 8.90};
constexpr Row kTitanium{2.214, 1.213, 0.7661, 4.51};
constexpr Row kIron{3.629, 1.958, 1.205, 7.87};
constexpr Row kChromium{2.856, 1.550, 0.9639, 7.19};
constexpr Row kAirEnergyAbsorption{0.06833, 0.04098, 0.03041, 0.0};  // mu_en/rho of dry air

double mix(double a, double wa, double b, double wb, double c = 0.0, double wc = 0.0) { return a * wa + b * wb + c * wc; }

Row row_of(XrayMaterial m) {
  switch (m) {
    case XrayMaterial::kSoftTissue: return kSoftTissue;
    case XrayMaterial::kBrain: return kBrain;
    case XrayMaterial::kCorticalBone: return kBone;
    case XrayMaterial::kLung: return {kSoftTissue.mu40, kSoftTissue.mu50, kSoftTissue.mu60, 0.26};
    case XrayMaterial::kAir: return {0.0, 0.0, 0.0, 0.0};
    case XrayMaterial::kIodine: return kIodine;
    case XrayMaterial::kPlatinum: return kPlatinum;
    case XrayMaterial::kNitinol:
      return {mix(kNickel.mu40, 0.558, kTitanium.mu40, 0.442), mix(kNickel.mu50, 0.558, kTitanium.mu50, 0.442),
              mix(kNickel.mu60, 0.558, kTitanium.mu60, 0.442), 6.45};
    case XrayMaterial::kStainlessSteel:
      return {mix(kIron.mu40, 0.71, kChromium.mu40, 0.19, kNickel.mu40, 0.10),
              mix(kIron.mu50, 0.71, kChromium.mu50, 0.19, kNickel.mu50, 0.10),
              mix(kIron.mu60, 0.71, kChromium.mu60, 0.19, kNickel.mu60, 0.10), 8.0};
  }
  return kSoftTissue;
}

// Log-log interpolation on the 40/50/60 keV grid, clamped to it.
double at_energy(const Row& r, double keV) {
  const double e = std::clamp(keV, 40.0, 60.0);
  if (r.mu50 <= 0.0) return 0.0;
  const bool low = e <= 50.0;
  const double e0 = low ? 40.0 : 50.0, e1 = low ? 50.0 : 60.0;
  const double m0 = low ? r.mu40 : r.mu50, m1 = low ? r.mu50 : r.mu60;
  const double t = std::log(e / e0) / std::log(e1 / e0);
  return std::exp(std::log(m0) + t * (std::log(m1) - std::log(m0)));
}

}  // namespace

std::string_view material_name(XrayMaterial m) {
  switch (m) {
    case XrayMaterial::kSoftTissue: return "soft tissue";
    case XrayMaterial::kBrain: return "brain";
    case XrayMaterial::kCorticalBone: return "cortical bone";
    case XrayMaterial::kLung: return "lung";
    case XrayMaterial::kAir: return "air";
    case XrayMaterial::kIodine: return "iodine";
    case XrayMaterial::kPlatinum: return "platinum";
    case XrayMaterial::kNitinol: return "nitinol";
    case XrayMaterial::kStainlessSteel: return "stainless steel";
  }
  return "soft tissue";
}

double mass_attenuation_cm2_g(XrayMaterial m, double keV) { return at_energy(row_of(m), keV); }
double density_g_cm3(XrayMaterial m) { return row_of(m).density; }
double linear_attenuation_per_mm(XrayMaterial m, double keV) { return 0.1 * mass_attenuation_cm2_g(m, keV) * density_g_cm3(m); }
double iodine_per_mm_per_mgI_ml(double keV) { return 0.1 * mass_attenuation_cm2_g(XrayMaterial::kIodine, keV) * 1e-3; }
double air_energy_absorption_cm2_g(double keV) { return at_energy(kAirEnergyAbsorption, keV); }

}  // namespace cathbox::flow
