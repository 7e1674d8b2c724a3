#include "session/replay.hpp"

namespace cathbox::session {

base::Result<std::unique_ptr<Replay>> Replay::open(const std::string& path, bool stop_at_mismatch,
                                                   const vessel::SurfaceMesh* surface) {
  base::Result<std::unique_ptr<RecordReader>> reader = RecordReader::open(path);
  if (!reader) return reader.error();
  return open(std::move(*reader), stop_at_mismatch, surface);
}

base::Result<std::unique_ptr<Replay>> Replay::open(std::unique_ptr<RecordReader> reader, bool stop_at_mismatch,
                                                   const vessel::SurfaceMesh* surface) {
  const RecordHeader& h = reader->header();
  SessionCaseLoad scene = session_case_from_record(h, surface);
  if (!scene) return base::Error{scene.error().message};
  SessionOptions options;
  options.period_us = h.period_us;
  options.hash_every = h.hash_every;
  options.held_tool = h.held_tool;
  options.end_at_target = false;  // a replay runs every recorded tick
  std::unique_ptr<Replay> r(new Replay());
  auto hand = std::make_unique<ReplayHand>(std::move(reader), stop_at_mismatch);
  r->hand_ = hand.get();
  r->session_ = std::make_unique<Session>(std::move(scene.value()), std::move(hand), options);
  return r;
}

std::int64_t Replay::step(std::int64_t ticks) {
  if (ticks < 0) {
    std::int64_t total = 0;
    while (!session_->over()) total += session_->step_virtual(10'000);
    return total;
  }
  return session_->step_virtual(ticks);
}

ReplayResult Replay::result() const {
  ReplayResult r;
  r.error = hand_->error();
  r.ticks = session_->ticks();
  r.recorded_ticks = hand_->reader().ticks_read();
  r.hashes_checked = hand_->hashes_checked();
  r.mismatch = hand_->first_mismatch();
  r.end = hand_->reader().end();
  r.metrics = session_->metrics();
  // The rig's own figure, as its record says (a replay runs in virtual time and drops none).
  if (r.end && r.end->haptic_dropped_ticks) {
    r.metrics.haptic_dropped_ticks = r.end->haptic_dropped_ticks;
    r.metrics.haptic_ticks = r.end->ticks;
  }
  return r;
}

ReplayResult replay_record(const std::string& path, TickObserver* observer, const vessel::SurfaceMesh* surface) {
  base::Result<std::unique_ptr<Replay>> replay = Replay::open(path, true, surface);
  if (!replay) {
    ReplayResult r;
    r.error = replay.error().message;
    return r;
  }
  if (observer != nullptr) (*replay)->session().add_observer(*observer);
  (*replay)->step(-1);
  return (*replay)->result();
}

}  // namespace cathbox::session
