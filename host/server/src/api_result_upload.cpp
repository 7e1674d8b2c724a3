// POST /results: a session record checked by replaying it, graded against its assignment's
// criteria, stored once per run.
#include <algorithm>
#include <cmath>

#include "api_call.hpp"
#include "api_work.hpp"
#include "server/json_input.hpp"
#include "server/pass_criteria.hpp"
#include "server/sha256.hpp"
#include "server/zstd_codec.hpp"

namespace cathbox::server::api {

namespace {

// A run already stored (the same bytes or the same decoded run): the stored result, unless it
// is another trainee's or was counted for another assignment (409).
Reply stored_again(Call& call, const ResultRow& existing, std::optional<std::int64_t> assignment_id) {
  if (existing.user_id != call.caller.user_id && !can_supervise(call.caller.role)) {
    return make_error(409, "record: this run was uploaded by another user");
  }
  // One run counts once: the same run for another assignment is a conflict, not a copy.
  if (assignment_id && existing.assignment_id != assignment_id) {
    return make_error(409, "record: already stored as result " + std::to_string(existing.id) +
                               (existing.assignment_id ? " for assignment " + std::to_string(*existing.assignment_id)
                                                       : std::string(" without an assignment")) +
                               "; a run counts for one assignment");
  }
  nlohmann::json j = result_json(existing);
  j["created"] = false;
  return json_response(200, j);
}

// Which header field of a record makes it another case than the assignment's: the first of the
// case text, the HCLM text and their file names that differs from the assigned version (the
// newest when the assignment names none).
std::string not_the_assigned_case(Call& call, const Assignment& a, const CheckedRecord& rec) {
  const std::optional<CaseVersion> v = call.c.store.case_version(a.case_name, a.case_version);
  const std::string which = "case '" + a.case_name + "'" + (v ? " version " + std::to_string(v->version) : std::string());
  const std::string tail = " is not the assignment's " + which + " (by content hash)";
  std::optional<CaseBundle> library;
  if (v) {
    if (std::optional<std::string> wire = call.c.store.case_bundle(v->id)) {
      if (Result<std::string> plain = zstd_decompress(*wire, kMaxBundleBytes * 2)) {
        if (Result<CaseBundle> b = parse_bundle_json(plain.value())) library = b.value();
      }
    }
  }
  const CaseBundle& r = rec.case_files;
  const std::string file = r.case_file.substr(0, 64);
  if (!library || r.case_text != library->case_text) return "record: header field 'case_text' (" + file + ")" + tail;
  if (r.hclm_text != library->hclm_text) return "record: header field 'vessel_text' (" + r.hclm_file.substr(0, 64) + ")" + tail;
  if (r.surface_bytes != library->surface_bytes) return "record: header field 'surface_bytes' (" + r.surface_file.substr(0, 64) + ")" + tail;
  if (r.case_file != library->case_file) return "record: header field 'case_file' (" + file + ")" + tail;
  if (r.surface_file != library->surface_file) return "record: header field 'surface_file' (" + r.surface_file.substr(0, 64) + ")" + tail;
  return "record: header field 'vessel_file' (" + r.hclm_file.substr(0, 64) + ")" + tail;
}

}  // namespace

Reply upload_result(Call& call) {
  const std::string& record = call.request.body;
  if (record.empty()) return make_error(400, "body: empty (send the record's bytes as application/octet-stream)");
  Result<std::optional<std::int64_t>> assignment_id = call.query_integer("assignment", 1, INT64_MAX);
  if (!assignment_id) return assignment_id.error();
  const std::string hash = sha256_hex(record);
  // Idempotent: the same bytes again answer the stored result without checking them again.
  if (std::optional<ResultRow> existing = call.c.store.result_by_hash(hash)) return stored_again(call, *existing, assignment_id.value());
  std::optional<Assignment> assignment;
  if (assignment_id.value()) {
    std::optional<Assignment> a = call.c.store.assignment(*assignment_id.value());
    if (!a || a->trainee_id != call.caller.user_id) {
      return make_error(404, "query 'assignment': no assignment " + std::to_string(*assignment_id.value()) + " for you");
    }
    assignment = std::move(a);
  }
  if (call.c.checker == nullptr) return make_error(503, "record checking is not available on this server");
  Result<CheckedRecord> checked = call.c.checker->check(record);
  if (!checked) return checked.error();
  const CheckedRecord& rec = checked.value();
  // The same run re-encoded (other compression or blocks, another informational field) is the
  // same result, whoever sends it.
  if (!rec.run_hash.empty()) {
    if (std::optional<ResultRow> existing = call.c.store.result_by_run(rec.run_hash)) {
      return stored_again(call, *existing, assignment_id.value());
    }
  }
  if (assignment && !rec.complete) {
    return make_error(422, "record: no end block (the recording stopped before the run ended); a cut record is kept for "
                           "debriefs without an assignment, never graded");
  }
  ResultRow row;
  row.content_hash = hash;
  row.run_hash = rec.run_hash;
  row.complete = rec.complete;
  row.user_id = call.caller.user_id;
  row.started_us = rec.started_us;
  row.duration_ms = rec.duration_ms;
  row.uploaded_us = call.c.clock.now_us();
  row.record_bytes = static_cast<std::int64_t>(record.size());
  // The record's case is named after the library version it matches, else after its file.
  const std::optional<CaseVersion> library = call.c.store.case_version_by_hash(sha256_hex(bundle_json(rec.case_files)));
  if (library) {
    row.case_name = library->name;
    row.case_version_id = library->id;
  } else {
    // Never a library case's name: a case that is not in the library is filed apart, whatever its
    // file is called (':' is in no library name).
    std::string stem = rec.case_files.case_file.substr(0, rec.case_files.case_file.rfind('.'));
    row.case_name = "unlisted:" + (check_slug(stem).empty() ? stem : std::string("unnamed"));
  }
  nlohmann::json metrics = nlohmann::json::object();
  for (const MetricValue& m : rec.metrics) metrics[m.name] = m.value;
  row.metrics_json = metrics.dump();
  if (assignment) {
    // The run must be on the library version the assignment names, byte for byte (case and HCLM,
    // by their content hash), not on a file that only carries its name.
    if (!library || row.case_name != assignment->case_name) return make_error(422, not_the_assigned_case(call, *assignment, rec));
    if (assignment->case_version != 0 && library->version != assignment->case_version) {
      return make_error(422, "record: case '" + row.case_name + "' version " + std::to_string(library->version) +
                                 " is not the assignment's version " + std::to_string(assignment->case_version));
    }
    row.assignment_id = assignment->id;
    Result<PassCriteria> criteria = PassCriteria::parse_text(assignment->criteria_json);
    row.passed = criteria && criteria.value().evaluate(metric_map(rec.metrics)).passed;
  }
  const std::uint64_t erasures_before = call.c.cache != nullptr ? call.c.cache->erasures() : 0;
  const ResultInsert stored = call.c.store.insert_result(row, rec.metrics, record);
  // The replay that checked the record also traced it: a first debrief needs no second replay.
  // Kept once the record is stored, and not when an erase (a delete) came in between.
  if (call.c.cache != nullptr && !rec.trace.empty() && stored.created) call.c.cache->put(trace_cache_key(hash), rec.trace, erasures_before);
  nlohmann::json j = result_json(stored.row);
  j["created"] = stored.created;
  ApiResponse r = json_response(stored.created ? 201 : 200, j);
  r.headers.emplace_back("Location", "/api/v1/results/" + std::to_string(stored.row.id));
  return r;
}

}  // namespace cathbox::server::api
