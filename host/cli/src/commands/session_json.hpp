#pragma once
// What `cathbox session info` and `metrics` print: a record's summary (read through without
// simulating) and the JSON shapes documented in host/cli/README.md (nlohmann-json).
#include <cstdint>
#include <map>
#include <string>

#include <nlohmann/json.hpp>

#include "session/record_reader.hpp"
#include "session/replay.hpp"

namespace cathbox::cli {

struct RecordSummary {
  std::int64_t ticks = 0;
  std::int64_t hashes = 0;
  std::int64_t box_changes = 0;
  std::int64_t target_reached_tick = -1;
  std::map<std::uint16_t, std::int64_t> controls;  // by kind
};

// Reads the rest of the record's ticks.
[[nodiscard]] RecordSummary summarise(session::RecordReader& reader);
[[nodiscard]] nlohmann::ordered_json info_json(const std::string& path, const session::RecordReader& reader,
                                       const RecordSummary& summary);
[[nodiscard]] std::string info_text(const std::string& path, const session::RecordReader& reader,
                                    const RecordSummary& summary);
[[nodiscard]] nlohmann::ordered_json metrics_json(const session::ReplayResult& result);

}  // namespace cathbox::cli
