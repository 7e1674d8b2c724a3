#pragma once
// X-ray attenuation of the materials in a fluoroscopic image, at the effective photon energy of
// the beam (default 50 keV, see xray_material.cpp): mass attenuation coefficients mu/rho from
// the NIST tables (Hubbell & Seltzer, NISTIR 5632, XCOM), densities, and linear attenuation
// coefficients per mm for Beer-Lambert: I = I0 exp(-sum mu_i l_i).
#include <string_view>

namespace cathbox::flow {

enum class XrayMaterial : unsigned char {
  kSoftTissue,      // ICRU four-component soft tissue, 1.00 g/cm^3
  kBrain,           // ICRU-44 grey/white matter, 1.04 g/cm^3
  kCorticalBone,    // ICRU-44 cortical bone, 1.92 g/cm^3
  kLung,            // soft tissue at inflated-lung density, 0.26 g/cm^3
  kAir,             // ~0
  kIodine,          // per g/cm^3 of iodine in solution (use iodine_per_mm)
  kPlatinum,        // marker bands, coil tips: 21.45 g/cm^3
  kNitinol,         // guidewire cores: 55.8 wt% Ni, 44.2 % Ti, 6.45 g/cm^3
  kStainlessSteel,  // braids, cores: 304 (Fe 71, Cr 19, Ni 10 wt%), 8.0 g/cm^3
};

inline constexpr double kDefaultEffectiveEnergy_keV = 50.0;

[[nodiscard]] std::string_view material_name(XrayMaterial m);
// Mass attenuation coefficient (cm^2/g) at an energy in [40, 60] keV (log-log between the
// NIST grid points 40, 50 and 60 keV).
[[nodiscard]] double mass_attenuation_cm2_g(XrayMaterial m, double keV = kDefaultEffectiveEnergy_keV);
[[nodiscard]] double density_g_cm3(XrayMaterial m);
// Linear attenuation coefficient, 1/mm.
[[nodiscard]] double linear_attenuation_per_mm(XrayMaterial m, double keV = kDefaultEffectiveEnergy_keV);
// Iodine in solution: 1/mm per mgI/mL (1 mgI/mL = 1e-3 g/cm^3 of iodine).
[[nodiscard]] double iodine_per_mm_per_mgI_ml(double keV = kDefaultEffectiveEnergy_keV);
// Mass energy-absorption coefficient of air (cm^2/g), for photon fluence per air kerma.
[[nodiscard]] double air_energy_absorption_cm2_g(double keV = kDefaultEffectiveEnergy_keV);

}  // namespace cathbox::flow
