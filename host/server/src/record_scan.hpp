#pragma once
// What the server reads from a record before it replays it: the run's length and its hash as
// decoded (ticks read and decompressed, nothing simulated), and the header's tools and entry
// against the case text the header carries. A record is checked against these before the replay
// meshes its vessel or runs a tick.
#include <cstdint>
#include <string>
#include <string_view>

#include "server/result.hpp"
#include "server/upload_limits.hpp"
#include "session/record_header.hpp"
#include "session/session_case.hpp"

namespace cathbox::server {

struct RecordScan {
  std::string run_hash;  // record_checker.hpp, CheckedRecord::run_hash
  std::int64_t ticks = 0;
  bool complete = false;  // the end block was read
};

// Reads every tick of the record: 422 with the reader's line on a bad record, 413 when the run
// is longer than limits.max_record_duration_s (found as soon as the ticks read pass it).
[[nodiscard]] Result<RecordScan> scan_record(std::string_view bytes, const UploadLimits& limits);

// The header's tools must be the tools its case text defines (the same specification, in the same
// order): 422 naming header field 'tools' otherwise. A record of a bare vessel file (no case text)
// ran the default guidewire.
[[nodiscard]] Status check_header_tools(const session::RecordHeader& header);

// The header's entry must be the case's: its `entry` line, else the vessel's default entry on the
// surface the replay built (`scene`, from the same HCLM text). 422 naming header field 'entry'.
[[nodiscard]] Status check_header_entry(const session::RecordHeader& header, const session::SessionCase& scene);

}  // namespace cathbox::server
