// Assignments: GET/POST /assignments, GET/DELETE /assignments/{id}. Results: uploads in
// api_result_upload.cpp, the rest in api_results.cpp.
#include <charconv>

#include "api_call.hpp"
#include "api_work.hpp"
#include "server/iso_time.hpp"
#include "server/json_input.hpp"
#include "server/pass_criteria.hpp"

namespace cathbox::server::api {

Result<std::int64_t> id_param(const std::string& text) {
  std::int64_t id = 0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), id);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || id < 1) {
    return make_error(400, "path: '" + text.substr(0, 32) + "' is not an id");
  }
  return id;
}

std::map<std::string, double> metric_map(const std::vector<MetricValue>& metrics) {
  std::map<std::string, double> m;
  for (const MetricValue& v : metrics) m[v.name] = v.value;
  return m;
}

namespace {

// The assignment, if the caller may see it (trainees: their own); 404 otherwise.
Result<Assignment> visible_assignment(Call& call, std::int64_t id) {
  std::optional<Assignment> a = call.c.store.assignment(id);
  if (!a || (!can_supervise(call.caller.role) && a->trainee_id != call.caller.user_id)) {
    return make_error(404, "no assignment " + std::to_string(id));
  }
  return *a;
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

}  // namespace cathbox::server::api
