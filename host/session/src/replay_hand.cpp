#include "session/replay_hand.hpp"

#include "session/control.hpp"

namespace cathbox::session {

ReplayHand::ReplayHand(std::unique_ptr<RecordReader> reader, bool stop_at_mismatch)
    : reader_(std::move(reader)), stop_at_mismatch_(stop_at_mismatch) {}

std::string ReplayHand::describe() const {
  return "replay of " + reader_->header().hand_description;
}

void ReplayHand::controls(std::int64_t tick, ControlSink& sink) {
  have_tick_ = false;
  if (out_of_ticks_) return;
  if (!reader_->next(current_)) {
    out_of_ticks_ = true;
    return;
  }
  // The reader numbers the ticks from 0 as the session does.
  if (current_.tick != tick) {
    out_of_ticks_ = true;
    return;
  }
  have_tick_ = true;
  for (std::size_t i = 0; i < current_.control_count; ++i) sink.push(current_.controls[i]);
}

void ReplayHand::read(std::int64_t, TickInput& in) {
  if (!have_tick_) return;
  for (std::size_t t = 0; t < in.tool_count; ++t) in.tools[t] = current_.tools[t];
  in.box = current_.box;
}

void ReplayHand::feel(const HandFeedback& fb) {
  if (!have_tick_ || !current_.state_hash) return;
  if (!fb.state_hash) {
    // The session hashes on the record's interval; a recorded hash on another tick is a
    // record made with another interval than its header says.
    if (!mismatch_) mismatch_ = HashMismatch{fb.tick, *current_.state_hash, 0};
    return;
  }
  ++hashes_checked_;
  if (*fb.state_hash != *current_.state_hash && !mismatch_) {
    mismatch_ = HashMismatch{fb.tick, *current_.state_hash, *fb.state_hash};
  }
}

bool ReplayHand::finished() const { return out_of_ticks_ || (stop_at_mismatch_ && mismatch_.has_value()); }

std::string ReplayHand::finish_reason() const {
  if (mismatch_) return "replay: state hash differs at tick " + std::to_string(mismatch_->tick);
  if (!reader_->error().empty()) return "replay: " + reader_->error();
  return reader_->finished() ? "replay: end of the record" : "replay: end of an unfinished record (no end block)";
}

}  // namespace cathbox::session
