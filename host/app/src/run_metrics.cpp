#include "app/run_metrics.hpp"

#include <algorithm>
#include <cstdio>

#include <glm/geometric.hpp>

namespace cathbox::app {

RunMetrics::RunMetrics(std::optional<glm::vec3> target_mm, double target_radius_mm,
                       std::int64_t contact_gap_us)
    : target_mm_(target_mm), target_radius_mm_(target_radius_mm), contact_gap_us_(contact_gap_us) {}

void RunMetrics::observe(const TickObservation& tick) {
  if (!started_) {
    started_ = true;
    start_us_ = tick.time_us;
    last_tip_mm_ = tick.tip_mm;
  }
  summary_.elapsed_us = tick.time_us - start_us_;
  summary_.path_length_mm += static_cast<double>(glm::distance(tick.tip_mm, last_tip_mm_));
  last_tip_mm_ = tick.tip_mm;

  if (tick.tip_in_contact) {
    const bool new_episode =
        !in_contact_ && (last_contact_us_ < 0 || tick.time_us - last_contact_us_ >= contact_gap_us_);
    if (new_episode) ++summary_.wall_contacts;
    in_contact_ = true;
    last_contact_us_ = tick.time_us;
  } else {
    in_contact_ = false;
  }
  summary_.peak_wall_force_mN = std::max(summary_.peak_wall_force_mN, tick.wall_force_mN);
  summary_.peak_hand_force_mN = std::max(summary_.peak_hand_force_mN, tick.hand_force_mN);

  if (target_mm_) {
    const double d = static_cast<double>(glm::distance(tick.tip_mm, *target_mm_));
    if (summary_.closest_to_target_mm < 0.0 || d < summary_.closest_to_target_mm) {
      summary_.closest_to_target_mm = d;
    }
    if (!summary_.reached_target && d <= target_radius_mm_) {
      summary_.reached_target = true;
      summary_.reached_at_us = tick.time_us;
    }
  }
}

std::string RunMetrics::format(const RunSummary& s) {
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "time            %.2f s\n"
                "path length     %.1f mm\n"
                "wall contacts   %d\n"
                "peak wall force %.1f mN\n"
                "peak hand force %.1f mN\n",
                static_cast<double>(s.elapsed_us) * 1e-6, s.path_length_mm, s.wall_contacts,
                s.peak_wall_force_mN, s.peak_hand_force_mN);
  std::string out = buf;
  if (s.closest_to_target_mm < 0.0) {
    out += "target          none in this case\n";
  } else if (s.reached_target) {
    std::snprintf(buf, sizeof buf, "target          reached at %.2f s\n",
                  static_cast<double>(s.reached_at_us) * 1e-6);
    out += buf;
  } else {
    std::snprintf(buf, sizeof buf, "target          not reached (closest %.1f mm)\n",
                  s.closest_to_target_mm);
    out += buf;
  }
  return out;
}

}  // namespace cathbox::app
