#include "flow/fluoro_dose.hpp"

#include <cmath>

#include "flow/xray_material.hpp"

namespace cathbox::flow {
namespace {

// ---------------------------------------------------------------------------------------------
// Detector dose targets: flat-panel angiography systems are set up for detector air kerma of the
// order of tens of nGy per fluoroscopy pulse and around a uGy per frame of a subtraction
// acquisition; the automatic dose-rate control that holds such targets is described in AAPM
// Report No. 125 (2012, functionality of ABC/ADRC logic in cardiovascular and interventional
// angiography systems). 40 nGy and 1 uGy are settings of this model, not measurements.
// Anti-scatter grids for angiography transmit ~60-75 % of the primary beam; 0.7 is used.
// Flat-panel detectors (CsI:Tl) have a DQE of ~0.6-0.7 at low spatial frequency at these
// energies; 0.65 is used.
// Photon fluence per air kerma: Phi/K = 1 / (E (mu_en/rho)_air); at 50 keV (mu_en/rho = 0.04098
// cm^2/g, NIST) that is 30.5 photons per mm^2 per nGy.
// Recursive temporal filter (frame averaging) of fluoroscopy displays: weight 0.25 keeps
// sqrt(w / (2 - w)) = 0.38 of the single-frame noise of a still scene.
// Reference check (README): at 15 pulses/s through the neuro phantom's ~1 % central
// transmission the model gives of the order of 1-3 Gy cm^2 per minute of fluoroscopy; dose
// surveys of diagnostic cerebral angiography (e.g. the RAD-IR study, Miller DL et al., J Vasc
// Interv Radiol 2003;14:711-27) report procedure totals of tens to a few hundred Gy cm^2.
// ---------------------------------------------------------------------------------------------
constexpr double kJoulePerKeV = 1.602176634e-16;

}  // namespace

double FluoroDose::detector_kerma_nGy(ExposureMode mode) const {
  return mode == ExposureMode::kSubtractionRun ? settings_.run_detector_nGy : settings_.fluoro_detector_nGy;
}

double FluoroDose::dap_per_pulse_Gy_cm2(ExposureMode mode, double field_area_cm2, double patient_transmission) const {
  if (!(patient_transmission > 0.0)) return 0.0;
  return detector_kerma_nGy(mode) * 1e-9 * field_area_cm2 / (patient_transmission * settings_.grid_primary_transmission);
}

double FluoroDose::entrance_kerma_mGy(ExposureMode mode, double patient_transmission, double sid_mm, double depth_mm) const {
  if (!(patient_transmission > 0.0) || !(depth_mm > 0.0)) return 0.0;
  const double at_detector_plane = detector_kerma_nGy(mode) * 1e-6 / (patient_transmission * settings_.grid_primary_transmission);
  return at_detector_plane * (sid_mm / depth_mm) * (sid_mm / depth_mm);
}

double FluoroDose::photons_per_mm2_per_nGy() const {
  const double energy_J = settings_.effective_keV * kJoulePerKeV;
  const double mu_en_m2_kg = air_energy_absorption_cm2_g(settings_.effective_keV) * 0.1;  // cm^2/g -> m^2/kg
  return 1e-9 / (energy_J * mu_en_m2_kg) * 1e-6;  // per m^2 per nGy -> per mm^2
}

double FluoroDose::quanta_per_pixel(ExposureMode mode, double pixel_mm) const {
  return detector_kerma_nGy(mode) * photons_per_mm2_per_nGy() * pixel_mm * pixel_mm * settings_.detective_quantum_efficiency;
}

double FluoroDose::log_noise_sigma(ExposureMode mode, double pixel_mm) const {
  const double n = quanta_per_pixel(mode, pixel_mm);
  if (!(n > 0.0)) return 0.0;
  double sigma = 1.0 / std::sqrt(n);
  if (mode == ExposureMode::kFluoroscopy) {
    const double w = settings_.temporal_filter_weight;
    sigma *= std::sqrt(w / (2.0 - w));
  }
  return sigma;
}

}  // namespace cathbox::flow
