#pragma once
// Exposure, dose-area product and quantum noise of fluoroscopy and of digital subtraction runs.
//
// Automatic dose-rate control keeps the air kerma at the detector (behind the patient and the
// anti-scatter grid) per pulse near a target: ~40 nGy for fluoroscopy, ~1 uGy per frame of a
// subtraction run (see fluoro_dose.cpp for sources). The tube output then follows the patient:
// the kerma entering the patient is the detector's divided by the primary transmission of
// patient and grid, so the dose-area product of one pulse is
//     DAP = K_detector * A_field(detector) / (T_patient * T_grid)
// (the product of kerma and area does not change along the beam, so it is the same at the
// detector as at the patient's entrance). T_patient is the phantom's mean transmission over the
// centre of the field (HeadPhantom::central_transmission), T_grid the grid's primary
// transmission. Scatter reaching the meter and table attenuation are left out.
//
// Quantum noise: at the detector a pixel collects N = K * Phi * a * DQE quanta, Phi the photon
// fluence per air kerma at the effective energy (1 / (E * (mu_en/rho)_air)), a the pixel area;
// the relative noise of the log image is 1/sqrt(N * T / T_ref) at a pixel of transmission T
// (T_ref = the controlled transmission), reduced by the display's recursive temporal filter.
namespace cathbox::flow {

enum class ExposureMode : unsigned char { kFluoroscopy, kSubtractionRun };

struct DoseSettings {
  double fluoro_detector_nGy = 40.0;      // per pulse
  double run_detector_nGy = 1000.0;       // per frame of a subtraction run
  double grid_primary_transmission = 0.7;
  double detective_quantum_efficiency = 0.65;
  double temporal_filter_weight = 0.25;   // recursive filter: shown = w * new + (1 - w) * previous
  double effective_keV = 50.0;
};

class FluoroDose {
 public:
  explicit FluoroDose(const DoseSettings& settings = {}) : settings_(settings) {}
  [[nodiscard]] const DoseSettings& settings() const { return settings_; }

  [[nodiscard]] double detector_kerma_nGy(ExposureMode mode) const;
  // Dose-area product of one pulse (Gy cm^2) for a field of `field_area_cm2` at the detector.
  [[nodiscard]] double dap_per_pulse_Gy_cm2(ExposureMode mode, double field_area_cm2, double patient_transmission) const;
  // Air kerma entering the patient per pulse at a point `depth_mm` from the source, for a
  // detector `sid_mm` from it (inverse square from the detector's kerma).
  [[nodiscard]] double entrance_kerma_mGy(ExposureMode mode, double patient_transmission, double sid_mm, double depth_mm) const;
  // Photons per mm^2 per nGy of air kerma at the effective energy.
  [[nodiscard]] double photons_per_mm2_per_nGy() const;
  // Quanta a pixel of `pixel_mm` collects per pulse at the controlled transmission.
  [[nodiscard]] double quanta_per_pixel(ExposureMode mode, double pixel_mm) const;
  // Standard deviation of the displayed log image at the controlled transmission (before the
  // 1/sqrt(T / T_ref) for other pixels), with the temporal filter for fluoroscopy.
  [[nodiscard]] double log_noise_sigma(ExposureMode mode, double pixel_mm) const;

 private:
  DoseSettings settings_;
};

}  // namespace cathbox::flow
