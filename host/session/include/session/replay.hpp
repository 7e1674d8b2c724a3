#pragma once
// Replaying a record: a fresh session on the record's own case (the HCLM and tools it carries)
// with a ReplayHand, run in virtual time. What the server runs on an uploaded record to refuse a
// tampered one, what `cathbox session replay --check` and `metrics` run, and what a debrief
// steps through (a TickObserver sees every tick's simulation state: tool shapes, tip, forces).
//
//   session::ReplayResult r = session::replay_record("run.cbxrec");
//   if (!r.error.empty()) ...            // "run.cbxrec: byte 812: block CRC mismatch"
//   else if (r.mismatch) ...             // state hash differs at r.mismatch->tick
//   else use(r.metrics);
#include <cstdint>
#include <memory>
#include <optional>
#include <string>

#include "session/metrics.hpp"
#include "session/record_reader.hpp"
#include "session/replay_hand.hpp"
#include "session/session.hpp"

namespace cathbox::session {

struct ReplayResult {
  std::string error;                    // a bad record ("FILE: byte N: what") or case; empty if none
  std::int64_t ticks = 0;               // ticks replayed
  std::int64_t recorded_ticks = 0;      // ticks the record holds (as far as it reads)
  std::int64_t hashes_checked = 0;
  std::optional<HashMismatch> mismatch;
  std::optional<RecordEnd> end;         // the record's end block (none: the recorder was killed)
  Metrics metrics;
  [[nodiscard]] bool matched() const { return error.empty() && !mismatch; }
};

class Replay {
 public:
  // Reads the header and builds the session; else the error line. `surface`: the vessel
  // surface made elsewhere (session_case.hpp), for a build that cannot mesh.
  [[nodiscard]] static base::Result<std::unique_ptr<Replay>> open(const std::string& path,
                                                                  bool stop_at_mismatch = true,
                                                                  const vessel::SurfaceMesh* surface = nullptr);
  [[nodiscard]] static base::Result<std::unique_ptr<Replay>> open(std::unique_ptr<RecordReader> reader,
                                                                  bool stop_at_mismatch = true,
                                                                  const vessel::SurfaceMesh* surface = nullptr);

  [[nodiscard]] const RecordHeader& header() const { return hand_->reader().header(); }
  [[nodiscard]] Session& session() { return *session_; }
  [[nodiscard]] const ReplayHand& hand() const { return *hand_; }

  // Runs up to `ticks` more ticks in virtual time (< 0: to the end); returns how many ran.
  std::int64_t step(std::int64_t ticks);
  [[nodiscard]] bool done() const { return session_->over(); }
  // Where the replay stands (complete once done()).
  [[nodiscard]] ReplayResult result() const;

 private:
  Replay() = default;
  ReplayHand* hand_ = nullptr;  // owned by the session
  std::unique_ptr<Session> session_;
};

// Opens `path` and replays it to the end (or the first differing hash), with `observer`
// watching every tick when given.
[[nodiscard]] ReplayResult replay_record(const std::string& path, TickObserver* observer = nullptr,
                                         const vessel::SurfaceMesh* surface = nullptr);

}  // namespace cathbox::session
