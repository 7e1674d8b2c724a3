#pragma once
// Internal to the API: the parsed request a handler sees, query helpers, JSON answers, and
// the handlers themselves (one file per resource: api_users, api_cases, api_work (assignments),
// api_result_upload and api_results (results), api_live, api_audit).
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/api.hpp"
#include "server/audit_log.hpp"

namespace cathbox::server::api {

struct Target {
  std::string path;
  std::vector<std::string> segments;  // percent-decoded
  std::map<std::string, std::string> query;
};

// 400 on bad percent-encoding, control characters or an over-long target.
[[nodiscard]] Result<Target> parse_target(std::string_view target);

struct Call {
  ApiContext& c;
  const ApiRequest& request;
  const Target& target;
  std::vector<std::string> params;  // the ':name' segments of the route, in order
  Caller caller;                    // empty user_id for the login route

  [[nodiscard]] std::optional<std::string> query(const std::string& name) const;
  [[nodiscard]] Result<std::optional<std::int64_t>> query_integer(const std::string& name, std::int64_t min, std::int64_t max) const;
  [[nodiscard]] Result<nlohmann::json> json_body() const;
  [[nodiscard]] Status require_supervisor(const std::string& what) const;
  [[nodiscard]] Status require_admin(const std::string& what) const;
};

using Reply = Result<ApiResponse>;

[[nodiscard]] ApiResponse json_response(int status, const nlohmann::json& body);
[[nodiscard]] ApiResponse no_content();

// Handlers.
Reply login(Call& call);
Reply logout(Call& call);
Reply me(Call& call);
Reply change_password(Call& call);
Reply list_users(Call& call);
Reply create_user(Call& call);
Reply update_user(Call& call);
Reply delete_user(Call& call);

Reply list_cases(Call& call);
Reply upload_case(Call& call);
Reply case_versions(Call& call);
Reply case_version(Call& call);
Reply case_bundle(Call& call);
Reply case_mesh(Call& call);

// Assignments (api_work.cpp); results: upload_result in api_result_upload.cpp, the rest in
// api_results.cpp.
Reply list_assignments(Call& call);
Reply create_assignment(Call& call);
Reply get_assignment(Call& call);
Reply delete_assignment(Call& call);
Reply upload_result(Call& call);
Reply list_results(Call& call);
Reply get_result(Call& call);
Reply get_result_record(Call& call);
Reply get_result_trace(Call& call);
Reply list_metrics(Call& call);

Reply live_rigs(Call& call);

Reply list_audit(Call& call);
// Appends the caller's action to the audit log (audit_log.hpp): who, now, from the request's address.
void audit(Call& call, const std::string& action, const std::string& target, const std::string& detail = {});
// The caller, now, the request's address: an audit row without its action yet.
[[nodiscard]] AuditEntry audit_entry(Call& call);

// The cached value (ApiContext::cache) of `key`, else build() now.
[[nodiscard]] Result<std::shared_ptr<const std::string>> cached(Call& call, const std::string& key,
                                                                const std::function<Result<std::string>()>& build,
                                                                bool* hit = nullptr);

// JSON shapes shared by several handlers.
[[nodiscard]] nlohmann::json user_json(const User& u);
[[nodiscard]] nlohmann::json case_json(const CaseVersion& v);
[[nodiscard]] nlohmann::json assignment_json(const Assignment& a);
[[nodiscard]] nlohmann::json result_json(const ResultRow& r);

}  // namespace cathbox::server::api
