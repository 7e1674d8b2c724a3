#pragma once
// What the server needs from a session record: the check that it replays exactly (every state
// hash matches), what case it ran, when, and its metrics. Implemented over host/session.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "server/case_bundle.hpp"
#include "server/result.hpp"
#include "server/store.hpp"

namespace cathbox::server {

struct CheckedRecord {
  CaseBundle case_files;  // the case and HCLM files the record carries verbatim
  std::string case_title; // the case file's `name` line
  std::int64_t started_us = 0;
  std::int64_t duration_ms = 0;
  std::vector<MetricValue> metrics;
  std::string trace;      // the debrief's trace from the same replay (see trace()); may be empty
  bool complete = true;   // false: no end block (the recorder was killed); never graded
  // SHA-256 of the run as decoded, not of the file's bytes: the header's run fields (case and
  // HCLM text, tools, entry, held tool, tick period, hash interval, start time) and every tick's
  // inputs and state hash. Compression, block boundaries and the informational fields (software
  // version, hand description, device) do not change it: the same run re-encoded is one result.
  std::string run_hash;
};

class RecordChecker {
 public:
  virtual ~RecordChecker() = default;
  // 422 with one line ("record: byte 4711: block CRC mismatch", "record: tick 12300: state
  // hash differs (tampered or broken)") when the record is refused.
  [[nodiscard]] virtual Result<CheckedRecord> check(std::string_view record_bytes) = 0;
  // The run for a debrief (GET /results/{id}/trace): the record replayed and sampled, as JSON
  // text (the format is in host/server/README.md, "Debrief trace"). Deterministic.
  [[nodiscard]] virtual Result<std::string> trace(std::string_view record_bytes) {
    (void)record_bytes;
    return make_error(503, "trace: this server cannot replay records");
  }
  // The metric names records carry (pass criteria may name only these).
  [[nodiscard]] virtual std::vector<std::string> metric_names() const = 0;
};

}  // namespace cathbox::server
