// The run's metrics gathered tick by tick (MetricsCollector; definitions in host/session/README.md,
// "Metrics"). The same as text and as named numbers: metrics_report.cpp.
#include "session/metrics.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

namespace cathbox::session {

MetricsCollector::MetricsCollector(MetricsSettings settings) : s_(std::move(settings)) {
  m_.has_target = s_.target_mm.has_value();
  m_.route_length_mm = s_.target_mm ? s_.route_length_mm : -1.0;
  m_.wall_force_threshold_mN = s_.wall_force_threshold_mN;
  if (!s_.route_segments.empty()) m_.wrong_branch_entries = 0;
}

void MetricsCollector::reset_held(const MetricsTick& t) {
  retracting_ = false;
  extreme_mm_ = t.held_insertion_mm;
  sample_count_ = 0;
}

void MetricsCollector::observe(const MetricsTick& t) {
  contact_began_ = false;
  target_just_reached_ = false;
  const std::int64_t dt_us = observe_time(t);
  observe_contact(t, dt_us);
  observe_target(t);
  observe_route(t);
  observe_retraction(t.held_insertion_mm);
  observe_speed(t.time_us, t.held_insertion_mm);
}

// Time, tool changes and the tip's path.
std::int64_t MetricsCollector::observe_time(const MetricsTick& t) {
  std::int64_t dt_us = 0;
  if (!started_) {
    started_ = true;
    start_us_ = t.time_us;
    last_tip_mm_ = t.tip_mm;
    reset_held(t);
  } else {
    dt_us = t.time_us - last_us_;
    if (t.tool_changed) {
      ++m_.tool_changes;
      reset_held(t);
      last_tip_mm_ = t.tip_mm;  // another tool's tip: not travel
    } else if (t.tool_replaced) {
      reset_held(t);
      last_tip_mm_ = t.tip_mm;  // a new coil's tip at the hub: not travel
    }
  }
  last_us_ = t.time_us;
  m_.procedure_time_us = t.time_us - start_us_;
  m_.tip_path_mm += static_cast<double>(glm::distance(t.tip_mm, last_tip_mm_));
  last_tip_mm_ = t.tip_mm;
  return dt_us;
}

// Contact episodes and wall/hand forces.
void MetricsCollector::observe_contact(const MetricsTick& t, std::int64_t dt_us) {
  if (t.tip_in_contact) {
    const bool new_episode = !in_contact_ && (last_contact_us_ < 0 || t.time_us - last_contact_us_ >= s_.contact_gap_us);
    if (new_episode) {
      ++m_.wall_contacts;
      contact_began_ = true;
    }
    in_contact_ = true;
    last_contact_us_ = t.time_us;
  } else {
    in_contact_ = false;
  }
  m_.peak_wall_force_mN = std::max(m_.peak_wall_force_mN, t.wall_force_mN);
  if (t.wall_force_mN > s_.wall_force_threshold_mN) m_.time_above_threshold_us += dt_us;
  m_.peak_hand_force_mN = std::max(m_.peak_hand_force_mN, t.hand_force_mN);
}

// Closest approach to the target, time to reach it, path efficiency.
void MetricsCollector::observe_target(const MetricsTick& t) {
  if (s_.target_mm) {
    const double d = static_cast<double>(glm::distance(t.tip_mm, *s_.target_mm));
    if (m_.closest_to_target_mm < 0.0 || d < m_.closest_to_target_mm) m_.closest_to_target_mm = d;
    if (!m_.target_reached && d <= s_.target_radius_mm) {
      m_.target_reached = true;
      target_just_reached_ = true;
      m_.time_to_target_us = t.time_us - start_us_;
      if (s_.route_length_mm > 0.0 && m_.tip_path_mm > 0.0) m_.path_efficiency = s_.route_length_mm / m_.tip_path_mm;
    }
  }
}

// Wrong branches: a change of the tip's segment (junctions and "none" do not count).
void MetricsCollector::observe_route(const MetricsTick& t) {
  if (!s_.route_segments.empty() && t.tip_segment >= 0 && t.tip_segment != last_segment_) {
    last_segment_ = t.tip_segment;
    if (std::find(s_.route_segments.begin(), s_.route_segments.end(), t.tip_segment) == s_.route_segments.end()) {
      ++m_.wrong_branch_entries;
    }
  }
}

// Retractions of the held tool.
void MetricsCollector::observe_retraction(double insertion_mm) {
  const double x = insertion_mm;
  if (!retracting_) {
    extreme_mm_ = std::max(extreme_mm_, x);
    if (x <= extreme_mm_ - s_.retraction_mm) {
      ++m_.retractions;
      retracting_ = true;
      extreme_mm_ = x;
    }
  } else {
    extreme_mm_ = std::min(extreme_mm_, x);
    if (x >= extreme_mm_ + s_.retraction_mm) {
      retracting_ = false;
      extreme_mm_ = x;
    }
  }
}

// Insertion speed over the window: against the newest sample at least a window old.
void MetricsCollector::observe_speed(std::int64_t time_us, double insertion_mm) {
  samples_[sample_head_] = {time_us, insertion_mm};
  sample_head_ = (sample_head_ + 1) % kSamples;
  sample_count_ = std::min(sample_count_ + 1, kSamples);
  for (std::size_t k = 1; k < sample_count_; ++k) {
    const Sample& old = samples_[(sample_head_ + kSamples - 1 - k) % kSamples];
    const std::int64_t span = time_us - old.time_us;
    if (span >= s_.speed_window_us) {
      const double speed = std::abs(insertion_mm - old.insertion_mm) * 1e6 / static_cast<double>(span);
      m_.peak_insertion_speed_mm_s = std::max(m_.peak_insertion_speed_mm_s, speed);
      break;
    }
  }
}

void MetricsCollector::set_coiling(const tool::CoilFigures& f) {
  m_.packing_density_pct = 100.0 * f.packing_density;
  m_.coil_length_mm = f.deployed_mm;
  m_.coil_herniations = f.herniations;
  m_.coil_herniated_peak_nodes = f.herniated_peak_nodes;
  m_.coil_herniated_depth_mm = f.herniated_depth_mm;
  m_.kick_back_mm = f.kick_back_mm;
  m_.kick_forward_mm = f.kick_forward_mm;
  const std::size_t kept = std::min<std::size_t>(static_cast<std::size_t>(f.detachments), tool::CoilFigures::kMaxDetachments);
  m_.coil_detach_force_mN.assign(f.detach_force_mN.begin(), f.detach_force_mN.begin() + static_cast<std::ptrdiff_t>(kept));
  m_.coil_detach_force_peak_mN = f.detach_force_peak_mN;
  m_.coil_detached_under_tension = f.detached_under_tension;
}

std::optional<double> Metrics::haptic_dropped_pct() const {
  if (!haptic_dropped_ticks) return std::nullopt;
  const auto ticks = static_cast<double>(haptic_ticks);
  const auto dropped = static_cast<double>(*haptic_dropped_ticks);
  return ticks + dropped > 0.0 ? 100.0 * dropped / (ticks + dropped) : 0.0;
}

double Metrics::unconverged_pct_max() const {
  double m = 0.0;
  for (const ToolConvergence& c : convergence) m = std::max(m, c.unconverged_pct());
  return m;
}

void MetricsCollector::set_convergence(std::size_t t, std::string_view tool, std::int64_t solved_ticks,
                                       std::int64_t unconverged_ticks) {
  if (m_.convergence.size() <= t) {
    m_.convergence.resize(t + 1);
    m_.convergence[t].tool = std::string(tool);
  }
  m_.convergence[t].solved_ticks = solved_ticks;
  m_.convergence[t].unconverged_ticks = unconverged_ticks;
}

void MetricsCollector::set_angioplasty(const tool::AngioplastyFigures& f) {
  if (f.lesion) {
    m_.stenosis_before_pct = f.stenosis_before_percent;
    m_.residual_stenosis_pct = f.residual_stenosis_percent;
  }
  m_.balloon_inflations = f.inflations;
  m_.balloon_inflated_s = f.inflated_time_s;
  m_.rupture_risk_events = f.rupture_risk_events;
}

void MetricsCollector::set_fluoroscopy(double time_s, double dose_area_product_mGy_cm2, int runs,
                                       double contrast_volume_ml) {
  m_.fluoroscopy_time_s = time_s;
  m_.dose_area_product_mGy_cm2 = dose_area_product_mGy_cm2;
  m_.fluoroscopy_runs = runs;
  m_.contrast_volume_ml = contrast_volume_ml;
}

}  // namespace cathbox::session
