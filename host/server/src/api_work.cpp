// Assignments and results: GET/POST /assignments, GET/DELETE /assignments/{id},
// POST /results, GET /results, GET /results/{id}[/record|/trace], GET /metrics
#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>

#include "api_call.hpp"
#include "server/iso_time.hpp"
#include "server/json_input.hpp"
#include "server/pass_criteria.hpp"
#include "server/sha256.hpp"
#include "server/zstd_codec.hpp"

namespace cathbox::server::api {

namespace {

Result<std::int64_t> id_param(const std::string& text) {
  std::int64_t id = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), id);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || id < 1) {
    return make_error(400, "path: '" + text.substr(0, 32) + "' is not an id");
  }
  return id;
}

// The assignment, if the caller may see it (trainees: their own); 404 otherwise.
Result<Assignment> visible_assignment(Call& call, std::int64_t id) {
  std::optional<Assignment> a = call.c.store.assignment(id);
  if (!a || (!can_supervise(call.caller.role) && a->trainee_id != call.caller.user_id)) {
    return make_error(404, "no assignment " + std::to_string(id));
  }
  return *a;
}

Result<ResultRow> visible_result(Call& call) {
  Result<std::int64_t> id = id_param(call.params[0]);
  if (!id) return id.error();
  std::optional<ResultRow> r = call.c.store.result(id.value());
  // Another trainee's result is answered as one that does not exist: a trainee cannot tell
  // which ids are taken.
  if (!r || (!can_supervise(call.caller.role) && r->user_id != call.caller.user_id)) {
    return make_error(404, "no result " + call.params[0]);
  }
  return *r;
}

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

std::map<std::string, double> metric_map(const std::vector<MetricValue>& metrics) {
  std::map<std::string, double> m;
  for (const MetricValue& v : metrics) m[v.name] = v.value;
  return m;
}

}  // namespace

nlohmann::json assignment_json(const Assignment& a) {
  nlohmann::json criteria = nlohmann::json::array();
  if (Result<PassCriteria> parsed = PassCriteria::parse_text(a.criteria_json)) criteria = parsed.value().to_json();
  nlohmann::json j = {{"id", a.id},
                      {"trainee", a.trainee},
                      {"case", a.case_name},
                      {"case_version", a.case_version == 0 ? nlohmann::json("latest") : nlohmann::json(a.case_version)},
                      {"criteria", std::move(criteria)},
                      {"note", a.note},
                      {"created_at", iso_time(a.created_us)}};
  j["due_at"] = a.due_us ? nlohmann::json(iso_time(*a.due_us)) : nlohmann::json(nullptr);
  return j;
}

nlohmann::json result_json(const ResultRow& r) {
  nlohmann::json metrics = nlohmann::json::object();
  if (Result<nlohmann::json> parsed = parse_json(r.metrics_json, "metrics")) metrics = parsed.value();
  nlohmann::json j = {{"id", r.id},
                      {"content_hash", r.content_hash},
                      {"trainee", r.user},
                      {"case", r.case_name},
                      {"started_at", iso_time(r.started_us)},
                      {"duration_s", static_cast<double>(r.duration_ms) / 1000.0},
                      {"uploaded_at", iso_time(r.uploaded_us)},
                      {"record_bytes", r.record_bytes},
                      {"complete", r.complete},
                      {"metrics", std::move(metrics)},
                      {"record_url", "/api/v1/results/" + std::to_string(r.id) + "/record"}};
  j["assignment"] = r.assignment_id ? nlohmann::json(*r.assignment_id) : nlohmann::json(nullptr);
  j["passed"] = r.passed ? nlohmann::json(*r.passed) : nlohmann::json(nullptr);
  if (!r.complete) j["cut"] = "the record has no end block (the recording stopped before the run ended): for debriefs, never graded";
  if (r.record_gone_us) {
    j["record_gone_at"] = iso_time(*r.record_gone_us);
    j.erase("record_url");
  }
  return j;
}

namespace {

// 410 for a result whose record the retention setting removed (the result itself stays).
Status record_kept(const ResultRow& r) {
  if (!r.record_gone_us) return Ok{};
  return make_error(410, "result " + std::to_string(r.id) + ": its record was removed by the retention setting at " + iso_time(*r.record_gone_us));
}

}  // namespace

Reply list_assignments(Call& call) {
  std::optional<std::int64_t> trainee;
  if (!can_supervise(call.caller.role)) {
    trainee = call.caller.user_id;
  } else if (const std::optional<std::string> name = call.query("trainee")) {
    const std::optional<User> u = call.c.store.user_by_name(*name);
    if (!u) return make_error(404, "query 'trainee': no user '" + name->substr(0, 64) + "'");
    trainee = u->id;
  }
  nlohmann::json list = nlohmann::json::array();
  for (const Assignment& a : call.c.store.list_assignments(trainee)) list.push_back(assignment_json(a));
  return json_response(200, {{"assignments", std::move(list)}});
}

Reply create_assignment(Call& call) {
  if (Status s = call.require_supervisor("assigning cases"); !s) return s.error();
  Result<nlohmann::json> body = call.json_body();
  if (!body) return body.error();
  FieldReader f(body.value());
  const std::string trainee = f.string("trainee", 64);
  Assignment a;
  a.case_name = f.string("case", 64);
  a.case_version = static_cast<int>(f.optional_integer("case_version", 1, 1'000'000).value_or(0));
  a.note = f.optional_string("note", 2000).value_or("");
  const std::optional<std::string> due = f.optional_string("due_at", 40);
  const auto criteria_it = body.value().find("criteria");
  f.only({"trainee", "case", "case_version", "criteria", "note", "due_at"});
  if (!f.ok()) return f.error();
  const std::vector<std::string> known = call.c.checker != nullptr ? call.c.checker->metric_names() : std::vector<std::string>{};
  Result<PassCriteria> criteria =
      criteria_it == body.value().end() ? PassCriteria::parse(nlohmann::json::array(), known) : PassCriteria::parse(*criteria_it, known);
  if (!criteria) return criteria.error();
  a.criteria_json = criteria.value().to_json().dump();
  if (due) {
    a.due_us = parse_iso_time(*due);
    if (!a.due_us) return make_error(400, "field 'due_at': expected YYYY-MM-DD or YYYY-MM-DDTHH:MM:SSZ");
  }
  const std::optional<User> u = call.c.store.user_by_name(trainee);
  if (!u) return make_error(404, "field 'trainee': no user '" + trainee + "'");
  a.trainee_id = u->id;
  if (!call.c.store.case_version(a.case_name, a.case_version)) {
    return make_error(404, "field 'case': no case '" + a.case_name + "'" +
                               (a.case_version != 0 ? " version " + std::to_string(a.case_version) : std::string()));
  }
  a.assigned_by = call.caller.user_id;
  const std::optional<Assignment> made = call.c.store.insert_assignment(a, call.c.clock.now_us());
  if (!made) return make_error(404, "field 'case': no case '" + a.case_name + "'");
  audit(call, "assignment.create", std::to_string(made->id), "trainee=" + trainee + " case=" + a.case_name);
  ApiResponse r = json_response(201, assignment_json(*made));
  r.headers.emplace_back("Location", "/api/v1/assignments/" + std::to_string(made->id));
  return r;
}

Reply get_assignment(Call& call) {
  Result<std::int64_t> id = id_param(call.params[0]);
  if (!id) return id.error();
  Result<Assignment> a = visible_assignment(call, id.value());
  if (!a) return a.error();
  nlohmann::json j = assignment_json(a.value());
  ResultFilter f;
  f.assignment_id = a.value().id;
  f.limit = 1000;
  nlohmann::json results = nlohmann::json::array();
  for (const ResultRow& r : call.c.store.list_results(f)) {
    results.push_back({{"id", r.id}, {"uploaded_at", iso_time(r.uploaded_us)}, {"passed", r.passed.value_or(false)}});
  }
  j["results"] = std::move(results);
  return json_response(200, j);
}

Reply delete_assignment(Call& call) {
  if (Status s = call.require_supervisor("deleting assignments"); !s) return s.error();
  Result<std::int64_t> id = id_param(call.params[0]);
  if (!id) return id.error();
  if (!call.c.store.delete_assignment(id.value())) return make_error(404, "no assignment " + call.params[0]);
  audit(call, "assignment.delete", std::to_string(id.value()));
  return no_content();
}

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

namespace {

// Whose results: a trainee only their own; a supervisor anyone's (query trainee=NAME) or all.
Status filter_trainee(Call& call, ResultFilter& f) {
  const std::optional<std::string> trainee_name = call.query("trainee");
  if (!can_supervise(call.caller.role)) {
    // The same answer for another trainee and for a name nobody has: names cannot be probed.
    if (trainee_name && *trainee_name != call.caller.name) return make_error(403, "query 'trainee': trainees see only their own results");
    f.user_id = call.caller.user_id;
  } else if (trainee_name) {
    const std::optional<User> u = call.c.store.user_by_name(*trainee_name);
    if (!u) return make_error(404, "query 'trainee': no user '" + trainee_name->substr(0, 64) + "'");
    f.user_id = u->id;
  }
  return Ok{};
}

// min.METRIC=X or max.METRIC=X: one end of a metric's range (at most 16 metrics).
Status filter_metric(const std::string& key, const std::string& value, ResultFilter& f) {
  const std::string metric = key.substr(4);
  double v = 0;
  const auto [end, ec] = std::from_chars(value.data(), value.data() + value.size(), v);
  if (metric.empty() || value.empty() || ec != std::errc() || end != value.data() + value.size() || !std::isfinite(v)) {
    return make_error(400, "query '" + key.substr(0, 72) + "': expected a number");
  }
  auto it = std::find_if(f.metrics.begin(), f.metrics.end(), [&](const MetricRange& m) { return m.name == metric; });
  if (it == f.metrics.end()) it = f.metrics.insert(f.metrics.end(), MetricRange{metric, std::nullopt, std::nullopt});
  (key[1] == 'i' ? it->min : it->max) = v;
  if (f.metrics.size() > 16) return make_error(400, "query: at most 16 metric ranges");
  return Ok{};
}

// One query parameter of GET results (trainee excepted) into the filter.
Status filter_by(Call& call, const std::string& key, const std::string& value, ResultFilter& f) {
  if (key == "case") {
    f.case_name = value;
  } else if (key == "assignment") {
    Result<std::optional<std::int64_t>> id = call.query_integer(key, 1, INT64_MAX);
    if (!id) return id.error();
    f.assignment_id = *id.value();
  } else if (key == "since" || key == "until") {
    const std::optional<std::int64_t> t = parse_iso_time(value);
    if (!t) return make_error(400, "query '" + key + "': expected YYYY-MM-DD or YYYY-MM-DDTHH:MM:SSZ");
    (key == "since" ? f.since_us : f.until_us) = t;
  } else if (key == "passed") {
    if (value != "true" && value != "false") return make_error(400, "query 'passed': expected true or false");
    f.passed = value == "true";
  } else if (key == "limit" || key == "offset") {
    Result<std::optional<std::int64_t>> n = call.query_integer(key, key == "limit" ? 1 : 0, key == "limit" ? 1000 : 1'000'000);
    if (!n) return n.error();
    (key == "limit" ? f.limit : f.offset) = static_cast<int>(*n.value());
  } else if (key.rfind("min.", 0) == 0 || key.rfind("max.", 0) == 0) {
    return filter_metric(key, value, f);
  } else {
    return make_error(400, "query '" + key.substr(0, 64) +
                               "': unknown (use trainee, case, assignment, since, until, passed, min.METRIC, max.METRIC, limit, offset)");
  }
  return Ok{};
}

}  // namespace

Reply list_results(Call& call) {
  ResultFilter f;
  if (Status s = filter_trainee(call, f); !s) return s.error();
  for (const auto& [key, value] : call.target.query) {
    if (key == "trainee") continue;
    if (Status s = filter_by(call, key, value, f); !s) return s.error();
  }
  nlohmann::json list = nlohmann::json::array();
  for (const ResultRow& r : call.c.store.list_results(f)) list.push_back(result_json(r));
  return json_response(200, {{"results", std::move(list)}, {"limit", f.limit}, {"offset", f.offset}});
}

namespace {

// The result and, under an assignment, each criterion against what was measured.
nlohmann::json evaluated_result_json(Call& call, const ResultRow& r) {
  nlohmann::json j = result_json(r);
  if (r.assignment_id) {
    if (const std::optional<Assignment> a = call.c.store.assignment(*r.assignment_id)) {
      Result<PassCriteria> criteria = PassCriteria::parse_text(a->criteria_json);
      if (criteria) j["evaluation"] = evaluation_json(criteria.value().evaluate(metric_map(call.c.store.result_metrics(r.id))));
    }
  }
  return j;
}

}  // namespace

Reply get_result(Call& call) {
  Result<ResultRow> r = visible_result(call);
  if (!r) return r.error();
  return json_response(200, evaluated_result_json(call, r.value()));
}

Reply get_result_trace(Call& call) {
  Result<ResultRow> r = visible_result(call);
  if (!r) return r.error();
  if (Status kept = record_kept(r.value()); !kept) return kept.error();
  if (call.c.checker == nullptr) return make_error(503, "trace: this server cannot replay records");
  const auto started = std::chrono::steady_clock::now();
  bool hit = false;
  Result<std::shared_ptr<const std::string>> trace = cached(
      call, trace_cache_key(r.value().content_hash),
      [&]() -> Result<std::string> {
        std::optional<std::string> bytes = call.c.store.result_record(r.value().id);
        if (!bytes) return make_error(404, "record missing");
        return call.c.checker->trace(*bytes);
      },
      &hit);
  if (!trace) return trace.error();
  // {"mesh_url", "result": GET /results/{id}, "trace": the replay sampled}; spliced, the trace is not re-parsed.
  ApiResponse out;
  // The library version the record ran (its vessel for the 3D view).
  nlohmann::json mesh_url = nullptr;
  for (const CaseVersion& v : call.c.store.case_versions(r.value().case_name)) {
    if (r.value().case_version_id && v.id == *r.value().case_version_id) {
      mesh_url = "/api/v1/cases/" + v.name + "/versions/" + std::to_string(v.version) + "/mesh";
    }
  }
  out.body = "{\"mesh_url\":" + safe_dump(mesh_url) + ",\"result\":" + safe_dump(evaluated_result_json(call, r.value())) +
             ",\"trace\":" + *trace.value() + "}";
  const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - started).count();
  out.headers.emplace_back("X-Cathbox-Trace", std::string(hit ? "cached" : "replayed") + "; " + std::to_string(ms) + " ms");
  return out;
}

Reply get_result_record(Call& call) {
  Result<ResultRow> r = visible_result(call);
  if (!r) return r.error();
  if (Status kept = record_kept(r.value()); !kept) return kept.error();
  std::optional<std::string> bytes = call.c.store.result_record(r.value().id);
  if (!bytes) return make_error(404, "record missing");
  ApiResponse out;
  out.content_type = "application/octet-stream";
  out.body = std::move(*bytes);
  out.headers.emplace_back("Content-Disposition", "attachment; filename=\"result-" + std::to_string(r.value().id) + ".cbxrec\"");
  out.headers.emplace_back("ETag", "\"" + r.value().content_hash + "\"");
  return out;
}

Reply list_metrics(Call& call) {
  nlohmann::json names = nlohmann::json::array();
  if (call.c.checker != nullptr) {
    for (const std::string& n : call.c.checker->metric_names()) names.push_back(n);
  }
  return json_response(200, {{"metrics", std::move(names)}});
}

}  // namespace cathbox::server::api
