#pragma once
// A record as the hand: each tick gives the recorded controls and tool positions, so a fresh
// simulator consumes exactly what the recorded one did; and after each step it compares the
// session's state hash with the recorded one where the record holds one. The hand finishes at
// the end of the record, at a damaged block (error()), or, with stop_at_mismatch, at the first
// hash that differs.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "session/hand.hpp"
#include "session/record_reader.hpp"

namespace cathbox::session {

struct HashMismatch {
  std::int64_t tick = 0;
  std::uint64_t recorded = 0;
  std::uint64_t replayed = 0;
};

class ReplayHand final : public Hand {
 public:
  explicit ReplayHand(std::unique_ptr<RecordReader> reader, bool stop_at_mismatch = true);

  [[nodiscard]] HandKind kind() const override { return HandKind::kReplay; }
  [[nodiscard]] std::string describe() const override;
  void controls(std::int64_t tick, ControlSink& sink) override;
  void read(std::int64_t tick, TickInput& input) override;
  void feel(const HandFeedback& feedback) override;
  [[nodiscard]] bool finished() const override;
  [[nodiscard]] std::string finish_reason() const override;

  [[nodiscard]] const RecordReader& reader() const { return *reader_; }
  // The tick just read (its recorded box status and events).
  [[nodiscard]] const TickRecord& current() const { return current_; }
  [[nodiscard]] std::int64_t hashes_checked() const { return hashes_checked_; }
  [[nodiscard]] const std::optional<HashMismatch>& first_mismatch() const { return mismatch_; }
  // The record's problem ("FILE: byte N: what"), empty when it read cleanly.
  [[nodiscard]] const std::string& error() const { return reader_->error(); }

 private:
  std::unique_ptr<RecordReader> reader_;
  bool stop_at_mismatch_;
  TickRecord current_;
  bool have_tick_ = false;
  bool out_of_ticks_ = false;
  std::int64_t hashes_checked_ = 0;
  std::optional<HashMismatch> mismatch_;
};

}  // namespace cathbox::session
