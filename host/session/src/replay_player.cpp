#include "session/replay_player.hpp"

#include <algorithm>

#include "session/clock.hpp"

namespace cathbox::session {

base::Result<std::unique_ptr<ReplayPlayer>> ReplayPlayer::open(const std::string& path) {
  std::unique_ptr<ReplayPlayer> p(new ReplayPlayer());
  p->path_ = path;
  // Its length: read through once (decoding only; fast).
  base::Result<std::unique_ptr<RecordReader>> scan = RecordReader::open(path);
  if (!scan) return scan.error();
  (*scan)->skip_to_end();
  p->total_ticks_ = (*scan)->ticks_read();
  p->problem_ = (*scan)->error();
  // Playing goes on past a mismatch: the debrief shows it rather than stopping there.
  base::Result<std::unique_ptr<Replay>> replay = Replay::open(path, false);
  if (!replay) return replay.error();
  p->replay_ = std::move(*replay);
  return p;
}

void ReplayPlayer::set_speed(double speed) { speed_ = std::clamp(speed, 0.05, 64.0); }

std::int64_t ReplayPlayer::lag_ticks() const {
  // While playing, being a frame or two behind the head is not seeking.
  return static_cast<std::int64_t>(100.0 * speed_) + 1;
}

void ReplayPlayer::seek(std::int64_t tick) {
  target_ = std::clamp<std::int64_t>(tick, 0, total_ticks_);
  head_ticks_ = static_cast<double>(target_);
}

bool ReplayPlayer::rebuild() {
  base::Result<std::unique_ptr<Replay>> fresh = Replay::open(path_, false);
  if (!fresh) {
    error_ = fresh.error().message;
    return false;
  }
  replay_ = std::move(*fresh);
  return true;
}

bool ReplayPlayer::advance(std::int64_t wall_dt_us, std::int64_t budget_us) {
  if (playing_) {
    const double period = static_cast<double>(header().period_us);
    head_ticks_ = std::min(static_cast<double>(total_ticks_), head_ticks_ + static_cast<double>(wall_dt_us) * speed_ / period);
    target_ = static_cast<std::int64_t>(head_ticks_);
    if (target_ >= total_ticks_) playing_ = false;
  }
  if (target_ < position() && !rebuild()) return false;
  const std::int64_t start = thread_cpu_time_us();
  while (position() < target_ && !replay_->done()) {
    replay_->step(std::min<std::int64_t>(target_ - position(), 50));
    if (budget_us >= 0 && thread_cpu_time_us() - start >= budget_us) break;
  }
  return true;
}

}  // namespace cathbox::session
