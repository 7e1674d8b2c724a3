#pragma once
// The REST API, /api/v1/..., as a function from request to response: no sockets, so tests
// and the fuzz target call it directly, and the HTTP layer (http_server.hpp) only moves bytes.
// Every endpoint and its example request and answer are in host/server/README.md.
//
// Rules every handler follows:
//  - every endpoint but POST /api/v1/login needs a valid bearer token (401 otherwise);
//  - roles are checked here, on the server (403 naming what is not allowed);
//  - bodies are JSON (except record uploads and bundle downloads); a bad body is 400 with one
//    line; a refused file (HCLM, case, record) is 422 with the reader's file:line line;
//  - errors are {"error": "one line"}; a database that is unreachable is 503 with Retry-After
//    (the client retries); nothing a client sends makes a 5xx otherwise.
#include <cstdint>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "server/artifact_cache.hpp"
#include "server/auth.hpp"
#include "server/case_library.hpp"
#include "server/clock.hpp"
#include "server/live_service.hpp"
#include "server/record_checker.hpp"
#include "server/store.hpp"

namespace cathbox::server {

struct ApiRequest {
  std::string method;  // "GET", "POST", ...
  std::string target;  // path and query: "/api/v1/results?trainee=alice"
  std::string authorization;
  std::string content_type;
  std::string accept_encoding;
  std::string if_none_match;
  std::string body;
  std::string remote_address;
};

struct ApiResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::vector<std::pair<std::string, std::string>> headers;
};

struct ApiContext {
  Store& store;
  Clock& clock;
  Auth& auth;
  CaseLibrary& cases;
  LiveService& live;
  RecordChecker* checker = nullptr;  // null: record uploads answer 503
  ArtifactCache* cache = nullptr;    // meshes and traces; null: built on every request
};

inline constexpr std::size_t kMaxJsonBodyBytes = 64 * 1024;
inline constexpr std::size_t kMaxCaseUploadBytes = 20 * 1024 * 1024;
inline constexpr std::size_t kMaxRecordBytes = 64 * 1024 * 1024;

class Api {
 public:
  explicit Api(ApiContext context) : c_(context) {}

  // Never throws; StoreError becomes 503, anything else unexpected 500 (a bug).
  [[nodiscard]] ApiResponse handle(const ApiRequest& request);
  // The largest body this request may carry (checked before the body is read).
  [[nodiscard]] static std::size_t body_limit(std::string_view method, std::string_view target);
  // POST /api/v1/login (however the path is spelled): the one body read without a token.
  [[nodiscard]] static bool is_login(std::string_view method, std::string_view target);
  // Requests that replay a record: run them on their own threads so the API stays quick.
  // Classified on the routed path ("/api/v1//results" is "/api/v1/results").
  [[nodiscard]] static bool is_heavy(std::string_view method, std::string_view target);

  [[nodiscard]] ApiContext& context() { return c_; }

 private:
  ApiContext c_;
};

// {"error": message} with the error's status (and Retry-After for 503 / 429).
[[nodiscard]] ApiResponse error_response(const Error& error);

}  // namespace cathbox::server
