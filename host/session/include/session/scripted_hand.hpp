#pragma once
// The scripted hand for headless runs: a simple autopilot that does what a trainee does. It
// pushes the tool along a path of waypoints (the vessel centerline from the entry to the
// target), twists the tool so that its curved tip bends the way the path turns a few
// millimetres ahead, slows down while the tip is turned the wrong way, and when the tool is stuck (the
// hand force rises or the tip makes no progress) pulls back a little, turns a quarter turn and
// tries again. Deterministic: its output depends only on its inputs.
//
// As a Hand it drives the held tool in the session (through a HandMapping without encoders)
// and finishes when it reaches the end of its path, gives up, or runs out of time.
#include <cstdint>
#include <string>
#include <vector>

#include <glm/vec3.hpp>

#include "session/hand.hpp"
#include "session/hand_mapping.hpp"

namespace cathbox::session {

struct HandObservation {
  glm::vec3 tip_mm{0.0F};
  glm::vec3 tip_direction{1.0F, 0.0F, 0.0F};  // unit, distal
  glm::vec3 tip_bend{0.0F, 1.0F, 0.0F};       // unit, the side the curved tip bends towards
  double hand_force_mN = 0.0;                 // axial force resisting the push
};

struct HandCommand {
  double insertion_mm = 0.0;
  double rotation_rad = 0.0;
};

struct ScriptedHandSettings {
  double push_mm_s = 15.0;
  double twist_gain_per_s = 4.0;       // rotation speed per radian of tip misalignment
  double max_twist_rad_s = 3.0;
  double lookahead_mm = 6.0;
  double stuck_force_mN = 250.0;
  double stuck_window_s = 1.0;         // no progress along the path over this long: stuck
  double min_progress_mm = 0.5;
  double back_off_mm = 6.0;
  double back_off_turn_rad = 1.5707963;
  int max_fruitless_retries = 8;       // retries in a row that end no further along the path
  double time_limit_s = 120.0;         // as a Hand: finishes after this long
  // As a Hand: finishes when the tip is this far from the path's end. 0 when the path ends at a
  // target (a tip on the wall 1 mm short of it can be further than the lumen radius from it);
  // 1 mm short of a leaf's cap is its end.
  double end_margin_mm = 1.0;
  // +1 when a positive proximal rotation turns the tip's bend positively about the distal
  // direction (right hand); -1 for the opposite convention.
  double rotation_sign = 1.0;
};

class ScriptedHand final : public Hand {
 public:
  ScriptedHand(std::vector<glm::vec3> path_mm, double max_insertion_mm,
               ScriptedHandSettings settings = {});

  // As a Hand, ticks of dt_s seconds (the session's period).
  void set_tick_s(double dt_s) { dt_s_ = dt_s; }
  [[nodiscard]] HandKind kind() const override { return HandKind::kScripted; }
  [[nodiscard]] std::string describe() const override { return "scripted hand"; }
  void hold(std::size_t tool, const ToolCommand& at) override { mapping_.hold(tool, at); }
  void read(std::int64_t tick, TickInput& input) override;
  void feel(const HandFeedback& feedback) override;
  [[nodiscard]] bool finished() const override;
  [[nodiscard]] std::string finish_reason() const override;

  // One haptic tick of dt seconds; returns the boundary the box would report.
  HandCommand step(double dt_s, const HandObservation& seen);

  // Arc length of the path's point closest to the tip (as last seen).
  [[nodiscard]] double progress_mm() const { return progress_mm_; }
  [[nodiscard]] double path_length_mm() const { return cumulative_.empty() ? 0.0 : cumulative_.back(); }
  [[nodiscard]] bool backing_off() const { return back_off_left_mm_ > 0.0 || turn_left_rad_ > 0.0; }
  [[nodiscard]] int retries() const { return retries_; }
  // Tried `max_fruitless_retries` times in a row without getting further: a trainee would stop.
  [[nodiscard]] bool gave_up() const { return fruitless_retries_ > s_.max_fruitless_retries; }
  [[nodiscard]] glm::vec3 point_at(double s_mm) const;

 private:
  [[nodiscard]] double closest_arc(const glm::vec3& p) const;

  std::vector<glm::vec3> path_;
  std::vector<double> cumulative_;
  double max_insertion_mm_;
  ScriptedHandSettings s_;
  HandCommand cmd_;
  double progress_mm_ = 0.0;
  double best_progress_mm_ = 0.0;
  double time_since_progress_s_ = 0.0;
  double back_off_left_mm_ = 0.0;
  double turn_left_rad_ = 0.0;
  int retries_ = 0;
  int fruitless_retries_ = 0;
  double progress_at_last_retry_mm_ = -1.0;
  bool started_ = false;
  // As a Hand.
  double dt_s_ = 1e-3;
  double elapsed_s_ = 0.0;
  HandObservation seen_;
  HandMapping mapping_;
};

}  // namespace cathbox::session
