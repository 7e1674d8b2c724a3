#include "session/scripted_hand.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <glm/geometric.hpp>

namespace cathbox::session {
namespace {
constexpr double kTrackWindow_mm = 3.0;
}  // namespace

ScriptedHand::ScriptedHand(std::vector<glm::vec3> path_mm, double max_insertion_mm,
                           ScriptedHandSettings settings)
    : path_(std::move(path_mm)), max_insertion_mm_(max_insertion_mm), s_(settings) {
  cumulative_.reserve(path_.size());
  double total = 0.0;
  for (std::size_t i = 0; i < path_.size(); ++i) {
    if (i > 0) total += static_cast<double>(glm::distance(path_[i], path_[i - 1]));
    cumulative_.push_back(total);
  }
}

glm::vec3 ScriptedHand::point_at(double s_mm) const {
  if (path_.empty()) return glm::vec3(0.0F);
  if (s_mm <= 0.0) return path_.front();
  const auto it = std::lower_bound(cumulative_.begin(), cumulative_.end(), s_mm);
  if (it == cumulative_.end()) return path_.back();
  const auto i = static_cast<std::size_t>(it - cumulative_.begin());
  if (i == 0) return path_.front();
  const double len = cumulative_[i] - cumulative_[i - 1];
  const float f = len > 0.0 ? static_cast<float>((s_mm - cumulative_[i - 1]) / len) : 0.0F;
  return path_[i - 1] + f * (path_[i] - path_[i - 1]);
}

double ScriptedHand::closest_arc(const glm::vec3& p) const {
  // Closest point on the polyline. After the first call it is searched within a few
  // millimetres of the last progress (the tip moves ~0.02 mm per tick), so that a path that
  // passes close to itself (the carotid siphon, a loop) cannot make the hand jump ahead.
  const double window = started_ ? kTrackWindow_mm : 1e300;
  double best_d2 = 1e300;
  double best_s = progress_mm_;
  for (std::size_t i = 0; i + 1 < path_.size(); ++i) {
    if (cumulative_[i] > progress_mm_ + window || cumulative_[i + 1] < progress_mm_ - window) continue;
    const glm::vec3 a = path_[i];
    const glm::vec3 ab = path_[i + 1] - a;
    const float len2 = glm::dot(ab, ab);
    const float t = len2 > 0.0F ? std::clamp(glm::dot(p - a, ab) / len2, 0.0F, 1.0F) : 0.0F;
    const glm::vec3 q = a + t * ab;
    const double d2 = static_cast<double>(glm::dot(p - q, p - q));
    if (d2 < best_d2) {
      best_d2 = d2;
      best_s = cumulative_[i] + static_cast<double>(t) * (cumulative_[i + 1] - cumulative_[i]);
    }
  }
  return best_s;
}

HandCommand ScriptedHand::step(double dt_s, const HandObservation& seen) {
  if (path_.size() < 2) return cmd_;
  progress_mm_ = closest_arc(seen.tip_mm);
  if (!started_) {  // progress is counted from where the tip starts
    started_ = true;
    best_progress_mm_ = progress_mm_;
  }

  if (backing_off()) {  // pulling back and turning
    const double pull = std::min(back_off_left_mm_, s_.push_mm_s * dt_s);
    back_off_left_mm_ -= pull;
    cmd_.insertion_mm = std::max(0.0, cmd_.insertion_mm - pull);
    const double turn = std::min(turn_left_rad_, s_.max_twist_rad_s * dt_s);
    turn_left_rad_ -= turn;
    cmd_.rotation_rad += turn;
    if (!backing_off()) {
      best_progress_mm_ = progress_mm_;
      time_since_progress_s_ = 0.0;
    }
    return cmd_;
  }

  // Turn the bend towards where the path goes: the signed angle, about the local path
  // direction, from the bend to the path's turn over the look-ahead. (The curved tip itself
  // points sideways, so the path, not the tip, is the reference.) Steer only when the path
  // ahead turns by more than ~8 degrees: on a straight stretch the bend may point anywhere.
  const glm::vec3 here = point_at(progress_mm_);
  const glm::vec3 axis_raw = point_at(progress_mm_ + 1.0) - point_at(progress_mm_ - 1.0);
  const glm::vec3 ahead = point_at(progress_mm_ + s_.lookahead_mm) - here;
  double error_rad = 0.0;
  if (glm::length(axis_raw) > 1e-4F) {
    const glm::vec3 t = glm::normalize(axis_raw);
    const glm::vec3 lateral = ahead - glm::dot(ahead, t) * t;
    const glm::vec3 bend = seen.tip_bend - glm::dot(seen.tip_bend, t) * t;
    if (glm::length(lateral) > 0.15F * glm::length(ahead) && glm::length(lateral) > 0.2F &&
        glm::length(bend) > 1e-3F) {
      const glm::vec3 d = glm::normalize(lateral);
      const glm::vec3 b = glm::normalize(bend);
      error_rad = std::atan2(static_cast<double>(glm::dot(t, glm::cross(b, d))),
                             static_cast<double>(glm::dot(b, d)));
    }
  }
  const double twist =
      std::clamp(s_.twist_gain_per_s * error_rad, -s_.max_twist_rad_s, s_.max_twist_rad_s);
  cmd_.rotation_rad += s_.rotation_sign * twist * dt_s;
  // Push, slower while the tip is turned away from where it should go.
  const double align = 0.5 * (1.0 + std::cos(error_rad));
  cmd_.insertion_mm = std::min(max_insertion_mm_, cmd_.insertion_mm + s_.push_mm_s * (0.25 + 0.75 * align) * dt_s);

  if (progress_mm_ > best_progress_mm_ + s_.min_progress_mm) {
    best_progress_mm_ = progress_mm_;
    time_since_progress_s_ = 0.0;
  } else {
    time_since_progress_s_ += dt_s;
  }
  if (seen.hand_force_mN > s_.stuck_force_mN || time_since_progress_s_ > s_.stuck_window_s) {
    ++retries_;
    fruitless_retries_ = best_progress_mm_ > progress_at_last_retry_mm_ + s_.min_progress_mm ? 0 : fruitless_retries_ + 1;
    progress_at_last_retry_mm_ = std::max(progress_at_last_retry_mm_, best_progress_mm_);
    back_off_left_mm_ = s_.back_off_mm;
    turn_left_rad_ = s_.back_off_turn_rad;
  }
  return cmd_;
}

void ScriptedHand::read(std::int64_t, TickInput& in) {
  max_insertion_mm_ = static_cast<double>(in.max_insertion_um[in.held]) * 1e-3;
  const HandCommand c = step(dt_s_, seen_);
  elapsed_s_ += dt_s_;
  in.tools[in.held] = mapping_.command({std::llround(c.insertion_mm * 1e3), std::llround(c.rotation_rad * 1e6)});
}

void ScriptedHand::feel(const HandFeedback& fb) {
  seen_.tip_mm = fb.tip_mm;
  seen_.tip_direction = fb.tip_direction;
  seen_.tip_bend = fb.tip_bend;
  seen_.hand_force_mN = fb.hand_force_mN;
}

bool ScriptedHand::finished() const {
  return gave_up() || elapsed_s_ >= s_.time_limit_s ||
         (path_length_mm() > 0.0 && progress_mm_ >= path_length_mm() - s_.end_margin_mm);
}

std::string ScriptedHand::finish_reason() const {
  char buf[128];
  if (gave_up()) {
    std::snprintf(buf, sizeof buf, "scripted hand: stuck %.0f mm along the way, gives up after %d tries", progress_mm_,
                  retries_);
  } else if (elapsed_s_ >= s_.time_limit_s) {
    std::snprintf(buf, sizeof buf, "scripted hand: time limit of %.0f s", s_.time_limit_s);
  } else {
    std::snprintf(buf, sizeof buf, "scripted hand: end of the path (%.0f mm)", path_length_mm());
  }
  return buf;
}

}  // namespace cathbox::session
