// Results: GET /results, GET /results/{id}[/record|/trace], GET /metrics (uploads:
// api_result_upload.cpp).
#include <charconv>
#include <chrono>

#include "api_call.hpp"
#include "api_work.hpp"
#include "server/iso_time.hpp"
#include "server/json_input.hpp"
#include "server/pass_criteria.hpp"

namespace cathbox::server::api {

namespace {

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

// 410 for a result whose record the retention setting removed (the result itself stays).
Status record_kept(const ResultRow& r) {
  if (!r.record_gone_us) return Ok{};
  return make_error(410, "result " + std::to_string(r.id) + ": its record was removed by the retention setting at " + iso_time(*r.record_gone_us));
}

}  // namespace

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
