#pragma once
// Playing a record back for a debrief: play, pause, change speed, seek — stepped by its caller
// (a render loop) in virtual time, so the same views draw a replay as a live run. Seeking
// forward runs the ticks in between as fast as the CPU allows; seeking backward rebuilds the
// replay from the record and runs up to the tick (the simulator cannot go back in time). Each
// advance() spends at most a CPU budget, so a long seek never freezes the caller: it shows
// seeking() and carries on at the next call.
#include <cstdint>
#include <memory>
#include <string>

#include "base/result.hpp"
#include "session/replay.hpp"

namespace cathbox::session {

class ReplayPlayer {
 public:
  // Opens the record (and reads it through once for its length); else one line.
  [[nodiscard]] static base::Result<std::unique_ptr<ReplayPlayer>> open(const std::string& path);

  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] const RecordHeader& header() const { return replay_->header(); }
  [[nodiscard]] Session& session() { return replay_->session(); }
  [[nodiscard]] const Replay& replay() const { return *replay_; }
  // Ticks in the record (as far as it reads) and the length in microseconds.
  [[nodiscard]] std::int64_t total_ticks() const { return total_ticks_; }
  [[nodiscard]] std::int64_t position() const { return replay_->session().ticks(); }
  [[nodiscard]] std::int64_t target() const { return target_; }
  // The record's problem after its readable part (a truncated tail), else empty.
  [[nodiscard]] const std::string& record_problem() const { return problem_; }

  void play() { playing_ = true; }
  void pause() { playing_ = false; }
  [[nodiscard]] bool playing() const { return playing_; }
  void set_speed(double speed);
  [[nodiscard]] double speed() const { return speed_; }
  // Moves the play head to `tick` (clamped to the record).
  void seek(std::int64_t tick);
  [[nodiscard]] bool seeking() const { return position() != target_ && (!playing_ || position() + lag_ticks() < target_); }

  // Called every frame: while playing the head moves by wall_dt_us x speed; then ticks run
  // towards it for at most budget_us of the calling thread's CPU time (< 0: no limit).
  // False when the replay had to be rebuilt and failed (error()).
  bool advance(std::int64_t wall_dt_us, std::int64_t budget_us);
  [[nodiscard]] const std::string& error() const { return error_; }

 private:
  ReplayPlayer() = default;
  [[nodiscard]] std::int64_t lag_ticks() const;
  bool rebuild();

  std::string path_;
  std::unique_ptr<Replay> replay_;
  std::int64_t total_ticks_ = 0;
  std::int64_t target_ = 0;
  double head_ticks_ = 0.0;  // the play head, fractional
  bool playing_ = false;
  double speed_ = 1.0;
  std::string problem_;
  std::string error_;
};

}  // namespace cathbox::session
