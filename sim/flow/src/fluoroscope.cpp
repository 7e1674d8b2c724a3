#include "flow/fluoroscope.hpp"

#include <cmath>

namespace cathbox::flow {

Fluoroscope::Fluoroscope(HeadPhantom phantom, const CArmPose& pose, const DoseSettings& dose)
    : phantom_(std::move(phantom)), carm_(pose), dose_(dose) {
  transmission_ = phantom_.central_transmission(carm_);
}

std::string Fluoroscope::set_pulse_rate(double per_s) {
  if (per_s != 7.5 && per_s != 15.0 && per_s != 30.0) return "pulse rate must be 7.5, 15 or 30 pulses per second";
  if (per_s != rate_hz_ && pressed_) {
    // Keep the pulse train continuous: restart the schedule at the last pulse.
    press_start_us_ = image_.pulse_time_us;
    press_pulses_ = 1;
  }
  rate_hz_ = per_s;
  return {};
}

std::string Fluoroscope::set_pose(const CArmPose& pose) {
  if (std::string e = check_pose(pose); !e.empty()) return e;
  if (pose == carm_.pose()) return {};
  carm_ = CArm(pose);
  transmission_ = phantom_.central_transmission(carm_);
  in_run_ = false;
  run_matches_pose_ = false;
  image_.roadmap_pulse = -1;
  last_press_pulse_ = -1;  // the previous image is from another angle: no mask from it
  return {};
}

bool Fluoroscope::capture_roadmap() {
  if (!run_matches_pose_ || run_peak_pulse_ < 0) return false;
  image_.roadmap_pulse = run_peak_pulse_;
  return true;
}

void Fluoroscope::clear_roadmap() { image_.roadmap_pulse = -1; }

FluoroTick Fluoroscope::tick(std::int64_t now_us, bool injecting) {
  FluoroTick out;
  if (last_tick_us_ >= 0 && pressed_) metrics_.fluoro_time_s += static_cast<double>(now_us - last_tick_us_) * 1e-6;
  last_tick_us_ = now_us;
  if (pedal_ && !pressed_) {
    press_start_us_ = now_us;
    press_pulses_ = 0;
  }
  if (!pedal_ && pressed_) {
    in_run_ = false;  // releasing the pedal ends a run
    last_press_pulse_ = -1;
  }
  pressed_ = pedal_;
  image_.beam_on = pedal_;
  if (!pedal_) return out;
  const std::int64_t due = press_start_us_ + std::llround(static_cast<double>(press_pulses_) * 1e6 / rate_hz_);
  if (now_us < due) return out;
  // A pulse.
  const std::int64_t pulse = metrics_.pulses++;
  ++press_pulses_;
  if (!in_run_ && injecting) {
    in_run_ = true;
    ++metrics_.runs;
    run_mask_ = last_press_pulse_ >= 0 ? last_press_pulse_ : pulse;
    run_peak_pulse_ = -1;
    run_peak_mg_ = -1.0;
    run_matches_pose_ = true;
    out.run_started = true;
  }
  const ExposureMode mode = in_run_ ? ExposureMode::kSubtractionRun : ExposureMode::kFluoroscopy;
  metrics_.dap_Gy_cm2 += dose_.dap_per_pulse_Gy_cm2(mode, carm_.field_area_cm2(), transmission_);
  image_.pulse = pulse;
  image_.pulse_time_us = now_us;
  image_.mode = mode;
  image_.run = in_run_ ? metrics_.runs : 0;
  image_.mask_pulse = in_run_ ? run_mask_ : -1;
  last_press_pulse_ = pulse;
  out.pulsed = true;
  out.pulse = pulse;
  return out;
}

void Fluoroscope::report_iodine_in_field(std::int64_t pulse, double mg) {
  if (!in_run_ || pulse != image_.pulse) return;
  if (mg > run_peak_mg_) {
    run_peak_mg_ = mg;
    run_peak_pulse_ = pulse;
  }
}

FieldIodine::FieldIodine(const ContrastTransport& t) {
  const std::size_t n = t.network().model().segments.size();
  for (std::uint32_t s = 0; s < n; ++s) {
    const std::span<const double> b = t.cell_bounds_mm(s);
    const double volume = t.network().segments()[s].volume_mm3 / static_cast<double>(b.size() - 1);
    for (std::size_t j = 0; j + 1 < b.size(); ++j) {
      centres_mm_.push_back(t.locator().point_at(s, 0.5 * (b[j] + b[j + 1])));
      volumes_mm3_.push_back(volume);
    }
  }
}

double FieldIodine::in_field_mg(const ContrastTransport& t, const CArm& carm) const {
  double mg = 0.0;
  std::size_t k = 0;
  const std::size_t n = t.network().model().segments.size();
  for (std::uint32_t s = 0; s < n; ++s) {
    for (double c : t.cell_concentrations(s)) {
      if (c > 0.0 && carm.depth_mm(centres_mm_[k]) > 0.0 && carm.in_field(carm.project_mm(centres_mm_[k]))) {
        mg += c * volumes_mm3_[k] * 1e-3;
      }
      ++k;
    }
  }
  return mg;
}

}  // namespace cathbox::flow
