// The record checker over host/session: a record is accepted only if it replays exactly (every
// state hash matches) on the case it carries; its metrics are what the replay measured, not
// anything the uploader claims.
#include <filesystem>
#include <utility>

#include "server/server_app.hpp"
#include "session/record_reader.hpp"
#include "session/replay.hpp"
#include "tool/case_file.hpp"

namespace cathbox::server {
namespace {

class SessionChecker final : public RecordChecker {
 public:
  Result<CheckedRecord> check(std::string_view bytes) override {
    std::string error;
    auto reader = session::RecordReader::from_bytes(std::vector<std::uint8_t>(bytes.begin(), bytes.end()), "record", error);
    if (!reader) return make_error(422, error);
    auto replay = session::Replay::open(std::move(reader), error);
    if (!replay) return make_error(422, error);
    replay->step(-1);
    const session::ReplayResult r = replay->result();
    if (!r.error.empty()) return make_error(422, r.error);
    if (r.mismatch) {
      return make_error(422, "record: tick " + std::to_string(r.mismatch->tick) +
                                 ": state hash differs (tampered or broken)");
    }
    if (r.hashes_checked == 0) return make_error(422, "record: no state hash to check (shorter than one hash interval)");
    const session::RecordHeader& h = replay->header();
    CheckedRecord out;
    // The library names files plainly (a case names its HCLM by its plain name); a record keeps
    // the paths they were opened from.
    out.case_files.case_file = std::filesystem::path(h.case_file).filename().string();
    out.case_files.case_text = h.case_text;
    out.case_files.hclm_file = std::filesystem::path(h.vessel_file).filename().string();
    out.case_files.hclm_text = h.vessel_text;
    out.case_title = h.case_name;
    out.started_us = h.start_unix_us;
    out.duration_ms = r.ticks * h.period_us / 1000;
    for (const session::NamedMetric& m : session::named_metrics(r.metrics)) out.metrics.push_back({m.name, m.value});
    return out;
  }

  [[nodiscard]] std::vector<std::string> metric_names() const override { return session::metric_names(); }
};

}  // namespace

std::unique_ptr<RecordChecker> make_session_checker() { return std::make_unique<SessionChecker>(); }

}  // namespace cathbox::server
