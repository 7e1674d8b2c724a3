#include "server/api.hpp"

#include <charconv>

#include "api_call.hpp"
#include "server/iso_time.hpp"
#include "server/json_input.hpp"

namespace cathbox::server {

namespace api {

namespace {

int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

Result<std::string> percent_decode(std::string_view s, bool plus_is_space, const char* where) {
  std::string out;
  out.reserve(s.size());
  for (std::size_t i = 0; i < s.size(); ++i) {
    char c = s[i];
    if (c == '%') {
      const int hi = i + 1 < s.size() ? hex_value(s[i + 1]) : -1;
      const int lo = i + 2 < s.size() ? hex_value(s[i + 2]) : -1;
      if (hi < 0 || lo < 0) return make_error(400, std::string(where) + ": bad %-escape at byte " + std::to_string(i));
      c = static_cast<char>(hi * 16 + lo);
      i += 2;
    } else if (c == '+' && plus_is_space) {
      c = ' ';
    }
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) {
      return make_error(400, std::string(where) + ": control character at byte " + std::to_string(i));
    }
    out += c;
  }
  if (!valid_utf8(out)) return make_error(400, std::string(where) + ": not UTF-8");
  return out;
}

}  // namespace

Result<Target> parse_target(std::string_view target) {
  if (target.size() > 4096) return make_error(414, "request target longer than 4096 bytes");
  if (target.empty() || target.front() != '/') return make_error(400, "request target must start with '/'");
  Target t;
  const std::size_t q = target.find('?');
  const std::string_view path = target.substr(0, q);
  t.path = std::string(path);
  std::size_t at = 1;
  while (at <= path.size()) {
    std::size_t end = path.find('/', at);
    if (end == std::string_view::npos) end = path.size();
    if (end > at) {
      Result<std::string> seg = percent_decode(path.substr(at, end - at), false, "path");
      if (!seg) return seg.error();
      t.segments.push_back(std::move(seg.value()));
    }
    at = end + 1;
  }
  if (q != std::string_view::npos) {
    std::string_view rest = target.substr(q + 1);
    while (!rest.empty()) {
      std::size_t amp = rest.find('&');
      const std::string_view pair = rest.substr(0, amp);
      rest = amp == std::string_view::npos ? std::string_view() : rest.substr(amp + 1);
      if (pair.empty()) continue;
      const std::size_t eq = pair.find('=');
      Result<std::string> key = percent_decode(pair.substr(0, eq), true, "query");
      if (!key) return key.error();
      Result<std::string> value = percent_decode(eq == std::string_view::npos ? std::string_view() : pair.substr(eq + 1), true, "query");
      if (!value) return value.error();
      if (t.query.size() >= 64) return make_error(400, "query: more than 64 parameters");
      t.query[key.value()] = value.value();
    }
  }
  return t;
}

std::optional<std::string> Call::query(const std::string& name) const {
  const auto it = target.query.find(name);
  if (it == target.query.end()) return std::nullopt;
  return it->second;
}

Result<std::optional<std::int64_t>> Call::query_integer(const std::string& name, std::int64_t min, std::int64_t max) const {
  const std::optional<std::string> text = query(name);
  if (!text) return std::optional<std::int64_t>();
  std::int64_t v = 0;
  const char* first = text->data();
  const char* last = first + text->size();
  const auto [end, ec] = std::from_chars(first, last, v);
  if (text->empty() || ec != std::errc() || end != last || v < min || v > max) {
    return make_error(400, "query '" + name + "': expected an integer " + std::to_string(min) + ".." + std::to_string(max));
  }
  return std::optional<std::int64_t>(v);
}

Result<nlohmann::json> Call::json_body() const { return parse_json_object(request.body, "body"); }

Status Call::require_supervisor(const std::string& what) const {
  if (can_supervise(caller.role)) return Ok{};
  return make_error(403, what + ": instructors and admins only");
}

Status Call::require_admin(const std::string& what) const {
  if (caller.role == Role::kAdmin) return Ok{};
  return make_error(403, what + ": admins only");
}

ApiResponse json_response(int status, const nlohmann::json& body) {
  ApiResponse r;
  r.status = status;
  r.body = safe_dump(body);
  return r;
}

Result<std::shared_ptr<const std::string>> cached(Call& call, const std::string& key,
                                                  const std::function<Result<std::string>()>& build, bool* hit) {
  if (call.c.cache != nullptr) return call.c.cache->get_or_build(key, build, hit);
  if (hit != nullptr) *hit = false;
  Result<std::string> built = build();
  if (!built) return built.error();
  return std::make_shared<const std::string>(std::move(built.value()));
}

ApiResponse no_content() {
  ApiResponse r;
  r.status = 204;
  r.content_type.clear();
  return r;
}

nlohmann::json user_json(const User& u) {
  return {{"id", u.id}, {"name", u.name}, {"role", role_name(u.role)}, {"disabled", u.disabled}, {"created_at", iso_time(u.created_us)}};
}

namespace {

using Handler = Reply (*)(Call&);

struct Route {
  const char* method;
  std::vector<const char*> pattern;  // after "api", "v1"; ":x" captures a segment
  Handler handler;
  bool needs_token;
};

const std::vector<Route>& routes() {
  static const std::vector<Route> table = {
      {"POST", {"login"}, login, false},
      {"POST", {"logout"}, logout, true},
      {"GET", {"me"}, me, true},
      {"POST", {"me", "password"}, change_password, true},
      {"GET", {"users"}, list_users, true},
      {"POST", {"users"}, create_user, true},
      {"PATCH", {"users", ":name"}, update_user, true},
      {"DELETE", {"users", ":name"}, delete_user, true},
      {"GET", {"cases"}, list_cases, true},
      {"POST", {"cases"}, upload_case, true},
      {"GET", {"cases", ":name"}, case_versions, true},
      {"GET", {"cases", ":name", "versions", ":version"}, case_version, true},
      {"GET", {"cases", ":name", "versions", ":version", "bundle"}, case_bundle, true},
      {"GET", {"cases", ":name", "versions", ":version", "mesh"}, case_mesh, true},
      {"GET", {"assignments"}, list_assignments, true},
      {"POST", {"assignments"}, create_assignment, true},
      {"GET", {"assignments", ":id"}, get_assignment, true},
      {"DELETE", {"assignments", ":id"}, delete_assignment, true},
      {"GET", {"results"}, list_results, true},
      {"POST", {"results"}, upload_result, true},
      {"GET", {"results", ":id"}, get_result, true},
      {"GET", {"results", ":id", "record"}, get_result_record, true},
      {"GET", {"results", ":id", "trace"}, get_result_trace, true},
      {"GET", {"metrics"}, list_metrics, true},
      {"GET", {"live", "rigs"}, live_rigs, true},
      {"GET", {"audit"}, list_audit, true},
  };
  return table;
}

bool matches(const Route& r, const std::vector<std::string>& segments, std::vector<std::string>* params) {
  if (segments.size() != r.pattern.size() + 2 || segments[0] != "api" || segments[1] != "v1") return false;
  std::vector<std::string> captured;
  for (std::size_t i = 0; i < r.pattern.size(); ++i) {
    const char* p = r.pattern[i];
    if (p[0] == ':') {
      captured.push_back(segments[i + 2]);
    } else if (segments[i + 2] != p) {
      return false;
    }
  }
  if (params != nullptr) *params = std::move(captured);
  return true;
}

ApiResponse dispatch(ApiContext& c, const ApiRequest& request) {
  Result<Target> target = parse_target(request.target);
  if (!target) return error_response(target.error());
  const Route* found = nullptr;
  std::vector<std::string> params;
  std::string allowed;
  for (const Route& r : routes()) {
    if (!matches(r, target.value().segments, nullptr)) continue;
    allowed += (allowed.empty() ? "" : ", ") + std::string(r.method);
    if (request.method == r.method) {
      found = &r;
      (void)matches(r, target.value().segments, &params);
    }
  }
  if (found == nullptr) {
    if (allowed.empty()) return error_response(make_error(404, "no endpoint " + target.value().path));
    ApiResponse r = error_response(make_error(405, request.method.substr(0, 16) + " is not allowed on " + target.value().path + " (allowed: " + allowed + ")"));
    r.headers.emplace_back("Allow", allowed);
    return r;
  }
  Call call{c, request, target.value(), std::move(params), Caller{}};
  if (found->needs_token) {
    Result<Caller> caller = c.auth.authenticate(request.authorization);
    if (!caller) {
      ApiResponse r = error_response(caller.error());
      r.headers.emplace_back("WWW-Authenticate", "Bearer");
      return r;
    }
    call.caller = std::move(caller.value());
  }
  Reply reply = found->handler(call);
  if (!reply) return error_response(reply.error());
  return std::move(reply.value());
}

}  // namespace

}  // namespace api

ApiResponse error_response(const Error& error) {
  std::string line = error.message;
  for (char& ch : line) {
    if (ch == '\n' || ch == '\r') ch = ' ';
  }
  ApiResponse r = api::json_response(error.status, {{"error", line}});
  if (error.status == 503 || error.status == 429) {
    const int default_s = error.status == 503 ? 1 : 60;
    r.headers.emplace_back("Retry-After", std::to_string(error.retry_after_s > 0 ? error.retry_after_s : default_s));
  }
  return r;
}

ApiResponse Api::handle(const ApiRequest& request) {
  try {
    return api::dispatch(c_, request);
  } catch (const StoreError& e) {
    if (e.kind() == StoreError::Kind::kUnavailable) return error_response(make_error(503, std::string("database unavailable, retry: ") + e.what()));
    return error_response(make_error(500, std::string("database error: ") + e.what()));
  } catch (const std::exception& e) {
    return error_response(make_error(500, std::string("internal error: ") + e.what()));
  }
}

namespace {

// The route a target names, as dispatch() sees it ("/api/v1//results/" is "api/v1/results"):
// the HTTP layer classifies on the same segments the router matches, so no spelling of a path
// reaches a handler with another class or body limit. Empty when the target does not parse.
std::string route_path(std::string_view target) {
  Result<api::Target> t = api::parse_target(target);
  if (!t) return {};
  std::string path;
  for (const std::string& seg : t.value().segments) path += "/" + seg;
  return path;
}

}  // namespace

std::size_t Api::body_limit(std::string_view method, std::string_view target) {
  if (method != "POST") return kMaxJsonBodyBytes;
  const std::string path = route_path(target);
  if (path == "/api/v1/results") return kMaxRecordBytes;
  if (path == "/api/v1/cases") return kMaxCaseUploadBytes;
  return kMaxJsonBodyBytes;
}

bool Api::is_login(std::string_view method, std::string_view target) { return method == "POST" && route_path(target) == "/api/v1/login"; }

bool Api::is_heavy(std::string_view method, std::string_view target) {
  const std::string path = route_path(target);
  const auto ends_with = [&path](std::string_view tail) { return path.size() > tail.size() && std::string_view(path).substr(path.size() - tail.size()) == tail; };
  if (method == "GET" && path.rfind("/api/v1/", 0) == 0 && (ends_with("/trace") || ends_with("/mesh"))) return true;
  return method == "POST" && (path == "/api/v1/results" || path == "/api/v1/cases");
}

}  // namespace cathbox::server
