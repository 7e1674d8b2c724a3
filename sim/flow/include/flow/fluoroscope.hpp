#pragma once
// The fluoroscopy unit's logic, without pixels: pulses while the pedal is pressed, the image
// the screen shows (the last pulse, held when the pedal is released), contrast runs and their
// subtraction masks, the roadmap, and the exposure metrics (fluoroscopy time, dose-area
// product, runs, pulses). Driven in virtual time by its owner (the session), one tick() per
// haptic tick; deterministic. A renderer turns a FluoroImage plus the image inputs captured at
// its pulse (tool nodes, contrast concentrations) into pixels.
//
// - Pulses: at the pulse rate (7.5, 15 or 30 per second) from the moment the pedal goes down:
//   pulse k of a press at t0 fires at t0 + round(k * 1e6 / rate) us.
// - Last-image hold: with the pedal up, the last pulse's image stays on screen.
// - Contrast run: a pulse that fires while contrast is being injected starts a run (if none is
//   running); every pulse until the pedal is released belongs to it and is exposed at the
//   subtraction dose. The run's mask is the pulse before it in the same press (contrast-free),
//   or its first pulse. The run's peak-opacification pulse is the one with the most iodine in
//   the collimated field (reported by the owner after each run pulse).
// - Roadmap: capture_roadmap() takes the peak pulse of the last run in the current C-arm pose
//   as the overlay on live fluoroscopy; clear_roadmap() removes it; moving the C-arm removes it
//   (and ends a run), since the old image no longer matches.
// - Dose: FluoroDose per pulse, with the phantom's central transmission for the pose.
#include <cstdint>
#include <string>
#include <vector>

#include "flow/c_arm.hpp"
#include "flow/contrast_transport.hpp"
#include "flow/fluoro_dose.hpp"
#include "flow/head_phantom.hpp"

namespace cathbox::flow {

struct FluoroImage {
  std::int64_t pulse = -1;          // the pulse shown; -1 before the first
  std::int64_t pulse_time_us = 0;
  bool beam_on = false;             // the pedal is pressed
  ExposureMode mode = ExposureMode::kFluoroscopy;  // of the shown pulse
  int run = 0;                      // run number of the shown pulse (1, 2, ...), 0: plain fluoroscopy
  std::int64_t mask_pulse = -1;     // the shown run's mask
  std::int64_t roadmap_pulse = -1;  // the pulse whose subtraction is overlaid, -1: none
  [[nodiscard]] bool last_image_hold() const { return !beam_on && pulse >= 0; }
  [[nodiscard]] bool subtracted() const { return run > 0; }
};

struct FluoroMetrics {
  double fluoro_time_s = 0.0;  // pedal pressed
  double dap_Gy_cm2 = 0.0;
  int runs = 0;
  std::int64_t pulses = 0;
};

struct FluoroTick {
  bool pulsed = false;          // a pulse fired at this tick: capture the image inputs now
  bool run_started = false;     // ... and it started a run
  std::int64_t pulse = -1;
};

class Fluoroscope {
 public:
  explicit Fluoroscope(HeadPhantom phantom = HeadPhantom::neuro(), const CArmPose& pose = {},
                       const DoseSettings& dose = {});

  // Controls; they act from the next tick.
  void set_pedal(bool pressed) { pedal_ = pressed; }
  [[nodiscard]] bool pedal() const { return pedal_; }
  // 7.5, 15 or 30 pulses per second; else an error and no change.
  [[nodiscard]] std::string set_pulse_rate(double per_s);
  [[nodiscard]] double pulse_rate() const { return rate_hz_; }
  // A new pose (check_pose); ends a run and removes the roadmap when it changes anything.
  [[nodiscard]] std::string set_pose(const CArmPose& pose);
  [[nodiscard]] bool capture_roadmap();
  void clear_roadmap();

  // Advances to now_us (non-decreasing).
  FluoroTick tick(std::int64_t now_us, bool injecting);
  // After a run pulse: the iodine then in the collimated field, for the peak.
  void report_iodine_in_field(std::int64_t pulse, double mg);

  [[nodiscard]] const FluoroImage& image() const { return image_; }
  [[nodiscard]] const FluoroMetrics& metrics() const { return metrics_; }
  [[nodiscard]] const CArm& carm() const { return carm_; }
  [[nodiscard]] const HeadPhantom& phantom() const { return phantom_; }
  [[nodiscard]] const FluoroDose& dose() const { return dose_; }
  [[nodiscard]] double patient_transmission() const { return transmission_; }
  // The current run's (or, between runs, the last run's) peak pulse; -1 when none.
  [[nodiscard]] std::int64_t peak_pulse() const { return run_peak_pulse_; }

 private:
  HeadPhantom phantom_;
  CArm carm_;
  FluoroDose dose_;
  double transmission_ = 1.0;
  double rate_hz_ = 15.0;
  bool pedal_ = false;
  bool pressed_ = false;          // the pedal was down at the last tick
  std::int64_t last_tick_us_ = -1;
  std::int64_t press_start_us_ = 0;
  std::int64_t press_pulses_ = 0; // pulses fired in this press
  std::int64_t last_press_pulse_ = -1;
  bool in_run_ = false;
  std::int64_t run_mask_ = -1;
  std::int64_t run_peak_pulse_ = -1;
  double run_peak_mg_ = -1.0;
  bool run_matches_pose_ = false; // the last run was made in the current pose
  FluoroImage image_;
  FluoroMetrics metrics_;
};

// Iodine (mg) in the contrast cells whose centres project into the C-arm's collimated field.
class FieldIodine {
 public:
  explicit FieldIodine(const ContrastTransport& transport);
  [[nodiscard]] double in_field_mg(const ContrastTransport& transport, const CArm& carm) const;

 private:
  std::vector<glm::dvec3> centres_mm_;   // per cell, in the transport's cell order
  std::vector<double> volumes_mm3_;
};

}  // namespace cathbox::flow
