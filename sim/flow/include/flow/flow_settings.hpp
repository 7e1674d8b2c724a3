#pragma once
// What the blood-flow model is built from besides the vessel geometry: the physiological
// defaults (below; sources in src/territory.cpp and sim/flow/README.md) and a case's overrides,
// which the case file gives as `flow ...` statements (sim/flow/README.md). Units are in the names.
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace cathbox::flow {

// A per-segment override from a case file; `line` locates it in errors found when the vessel
// model is known (an id the model lacks, a segment end that is not free).
struct SegmentSetting {
  std::int32_t segment_id = 0;
  double value = 0.0;        // mL/min for inflows and outlets, exchange fraction for closed ends
  std::size_t line = 0;
  friend bool operator==(const SegmentSetting&, const SegmentSetting&) = default;
};

struct FlowSettings {
  // Apparent viscosity of whole blood at the shear rates of large arteries (> 100 1/s),
  // haematocrit ~45 %: 3.5 mPa.s, treated as Newtonian.
  double viscosity_mPa_s = 3.5;
  // Resting adult cardiac output.
  double cardiac_output_ml_min = 5000.0;
  // Share of the cardiac output that goes to the brain (total cerebral blood flow).
  double cerebral_fraction = 0.15;
  // Mean arterial and venous pressure: the terminal resistances drop the one to the other.
  double arterial_pressure_mmHg = 93.0;
  double venous_pressure_mmHg = 5.0;
  // Terminal resistances calibrated so that, with the arterial pressure at the inlet, every
  // outlet drains its target flow (autoregulated territories); else fixed at
  // (arterial - venous) / target, so the vessels' own resistance lowers the flows a little.
  bool calibrate_terminals = true;
  // Wall shear stress of Murray's law for outlets without a named territory: Q = pi tau r^3 / (4 mu).
  double wall_shear_stress_Pa = 1.2;
  // Axial dispersion of contrast: D = dispersion_radii * r * |v| (a dispersivity of that many
  // local radii).
  double dispersion_radii = 1.0;
  // A blind end (aneurysm sac) exchanges this fraction of its junction's through-flow.
  double sac_exchange_fraction = 0.1;
  // Pulsatility: 0 bpm is steady flow. Otherwise every flow is scaled by
  // 1 + (PI / 2) sin(2 pi t * bpm / 60) (one harmonic with the given pulsatility index).
  double heart_rate_bpm = 0.0;
  double pulsatility_index = 0.0;

  std::vector<SegmentSetting> inflows;   // `flow inflow SEG ML_PER_MIN`: a root's inflow
  std::vector<SegmentSetting> outlets;   // `flow outlet SEG ML_PER_MIN`: an outlet's target flow
  std::vector<SegmentSetting> closed;    // `flow closed SEG [FRACTION]`: a blind distal end
  std::string source;                    // file the overrides came from (errors name it)
  friend bool operator==(const FlowSettings&, const FlowSettings&) = default;
};

}  // namespace cathbox::flow
