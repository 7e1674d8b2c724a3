#pragma once
// The numbers of the fluoroscopic image model that are not physics constants (those live in
// sim/flow: xray_material.hpp, fluoro_dose.hpp): how log attenuation maps to grey on the
// monitor, the subtraction and roadmap windows, how thin tools are drawn, and the noise field.
// No GL; FluoroRenderer passes them to its shaders. docs/trainer/fluoroscopy.md, "The fluoroscopic
// view", describes the whole model.
#include <cstdint>
#include <vector>

namespace cathbox::app {

struct FluoroDisplay {
  // Fluoroscopy: grey = 1 / (1 + exp(-slope * (L_ref - L_shown + noise))), L the line integral
  // of mu (Beer-Lambert exponent) and L_ref = -ln(T_ref) at the dose control's reference
  // transmission: the controlled part of the patient is mid grey, thinner parts brighter.
  float fluoro_slope = 1.2F;
  // Dynamic range compression, as a fluoroscopy unit's image processing does: the anatomy's
  // broad variation (the phantom's L_p) is shown at this fraction, detail (contrast, tools) in
  // full: L_shown = L_ref + anatomy_gain * (L_p - L_ref) + (L - L_p).
  float anatomy_gain = 0.5F;
  // Subtraction (DSA): grey = background - gain * (L_run - L_mask + noise): contrast dark on a
  // light grey.
  float dsa_background = 0.72F;
  float dsa_gain = 0.6F;
  // Roadmap: the peak subtraction frame's r = L_peak - L_mask brightens the live grey g as a
  // screen blend, g + (1 - g) (1 - exp(-gain r)): the filled vessels bright on live
  // fluoroscopy without saturating, so the wire stays a dark line inside them.
  float roadmap_gain = 0.8F;
  // The detector's pixel pitch in fluoroscopy (mm at the detector): flat panels read
  // fluoroscopy out 2 x 2 binned (more signal per pixel, a quarter of the data; subtraction
  // runs at full resolution), 2 x 2 of a 150-200 um native pitch. Where a display pixel is
  // finer than this, a fluoroscopy image is made at the readout's pixels (fewer: its noise per
  // pixel from the binned pixel's quanta) and scaled to the display bilinearly; 0: never binned.
  float fluoro_readout_pitch_mm = 0.4F;
  bool noise = true;  // quantum noise (off: the expected image, for tests that compare images)
};

// A tool thinner than a pixel would fall between pixel centres: it is drawn at least
// `min_px` detector pixels (at the isocentre's magnification) in radius, its attenuation
// scaled by (r / r_drawn)^2 so that its integral across the line (mu * pi r^2) is kept.
struct ThinLine {
  float radius_mm = 0.0F;
  float mu_scale = 1.0F;
};
// The image's pixels for a width x height display whose pixel is `display_pixel_mm` at the
// detector: fewer when the detector's readout pitch (`readout_pitch_mm`, 0: never binned) is
// coarser, the same aspect (FluoroDisplay::fluoro_readout_pitch_mm).
struct ImageMatrix {
  int width = 0;
  int height = 0;
};
[[nodiscard]] ImageMatrix readout_matrix(int width, int height, double display_pixel_mm, double readout_pitch_mm);

[[nodiscard]] ThinLine thin_line(float radius_mm, double patient_pixel_mm, double min_px = 1.0);

// Quantum noise of pulse `pulse` at pixel (x, y): approximately standard normal (the sum of the
// four bytes of an integer hash of pixel and pulse, centred and scaled: Irwin-Hall with n = 4),
// independent between pixels and pulses, and the same every time for the same pulse. The
// composite shader computes the same hash; this is its reference.
[[nodiscard]] std::uint32_t pulse_seed(std::int64_t pulse);
[[nodiscard]] float pixel_noise(std::uint32_t x, std::uint32_t y, std::uint32_t seed);

}  // namespace cathbox::app
