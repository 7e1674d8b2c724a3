#pragma once
// What the end-of-run panel reports, accumulated tick by tick on the haptic thread: elapsed
// time, the path the tip travelled, the number of wall contacts (episodes in which the tip
// touches the wall, separated by at least `contact_gap_us` without contact), the peak wall
// force and the peak hand force, and whether (and when) the tip reached the target.
#include <cstdint>
#include <optional>
#include <string>

#include <glm/vec3.hpp>

namespace cathbox::app {

struct RunSummary {
  std::int64_t elapsed_us = 0;
  double path_length_mm = 0.0;
  int wall_contacts = 0;
  double peak_wall_force_mN = 0.0;
  double peak_hand_force_mN = 0.0;
  bool reached_target = false;
  std::int64_t reached_at_us = -1;
  double closest_to_target_mm = -1.0;  // < 0 when the case has no target
};

struct TickObservation {
  std::int64_t time_us = 0;
  glm::vec3 tip_mm{0.0F};
  bool tip_in_contact = false;
  double wall_force_mN = 0.0;  // largest normal force of this tick's contacts
  double hand_force_mN = 0.0;  // magnitude of the axial force felt at the hand
};

class RunMetrics {
 public:
  explicit RunMetrics(std::optional<glm::vec3> target_mm = std::nullopt,
                      double target_radius_mm = 2.0, std::int64_t contact_gap_us = 20'000);

  void observe(const TickObservation& tick);
  [[nodiscard]] const RunSummary& summary() const { return summary_; }
  [[nodiscard]] bool has_target() const { return target_mm_.has_value(); }

  // One line per figure, for stdout and the log.
  [[nodiscard]] static std::string format(const RunSummary& s);

 private:
  std::optional<glm::vec3> target_mm_;
  double target_radius_mm_;
  std::int64_t contact_gap_us_;
  RunSummary summary_;
  bool started_ = false;
  std::int64_t start_us_ = 0;
  glm::vec3 last_tip_mm_{0.0F};
  bool in_contact_ = false;
  std::int64_t last_contact_us_ = -1;
};

}  // namespace cathbox::app
