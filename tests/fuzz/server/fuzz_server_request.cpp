// Fuzzes the server's request parsers end to end: the first byte picks what the rest is.
//   0: raw HTTP/1.1 request bytes -> Beast's request parser (the server's limits) -> the API
//   1: a JSON body for one of the POST/PATCH endpoints (second byte picks it)
//   2: a message from a streaming rig (LiveService::message)
//   3: a watcher's message
//   4: a request target (path and query) for GET
// The API runs on an in-memory SQLite store with a logged-in admin and trainee, so handlers
// past authentication are reached. Property: nothing a client sends gives a 5xx or a crash.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include <boost/beast/http.hpp>

#include "server/live_schema.hpp"
#include "server/server_app.hpp"

namespace {

using namespace cathbox::server;

struct World {
  std::unique_ptr<ServerCore> core;
  std::string admin;
  std::string trainee;
  std::optional<Publisher> publisher;
};

World& world() {
  static World w = [] {
    World out;
    ServerConfig config;
    config.db_url = "sqlite::memory:";
    config.argon2 = test_argon2_params();
    config.auth.address_burst = 1 << 30;  // throttling would hide the handlers behind 429
    config.auth.max_failures = 1 << 30;
    Result<std::unique_ptr<ServerCore>> core = ServerCore::open(config);
    if (!core) {
      std::fprintf(stderr, "server core: %s\n", core.error().message.c_str());
      std::abort();
    }
    out.core = std::move(core.value());
    const auto require = [](const auto& result, const char* what) {
      if (!result) {
        std::fprintf(stderr, "%s: %s\n", what, result.error().message.c_str());
        std::abort();
      }
    };
    require(out.core->auth().create_user("root", Role::kAdmin, "password-123"), "create root");
    require(out.core->auth().create_user("alice", Role::kTrainee, "password-123"), "create alice");
    const auto root_login = out.core->auth().login("root", "password-123", "fuzz");
    require(root_login, "login root");
    const auto alice_login = out.core->auth().login("alice", "password-123", "fuzz");
    require(alice_login, "login alice");
    out.admin = root_login.value().token;
    out.trainee = alice_login.value().token;
    Result<Caller> alice = out.core->auth().authenticate(out.trainee);
    require(alice, "authenticate alice");
    Result<Publisher> p = out.core->live().start(alice.value(), "rig-1", "ybif", 0, std::nullopt);
    if (!p) {
      std::fprintf(stderr, "live start: %s\n", p.error().message.c_str());
      std::abort();
    }
    out.publisher = std::move(p.value());
    return out;
  }();
  return w;
}

void check(const ApiResponse& r) {
  // A build without host/session answers record uploads 503 (no checker): not the client's doing.
  if (r.status == 503 && r.body.find("record checking is not available") != std::string::npos) return;
  if (r.status >= 500 || r.status < 200) {
    std::fprintf(stderr, "status %d: %s\n", r.status, r.body.c_str());
    std::abort();
  }
}

ApiResponse call(World& w, const std::string& method, const std::string& target, const std::string& body, bool as_admin) {
  ApiRequest req;
  req.method = method;
  req.target = target;
  req.body = body;
  req.authorization = "Bearer " + (as_admin ? w.admin : w.trainee);
  req.remote_address = "fuzz";
  return w.core->api().handle(req);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  World& w = world();
  const int mode = data[0] % 5;
  const bool as_admin = (data[1] & 0x80) != 0;
  const std::string rest(reinterpret_cast<const char*>(data + 2), size - 2);
  switch (mode) {
    case 0: {
      namespace http = boost::beast::http;
      http::request_parser<http::string_body> parser;
      parser.header_limit(16 * 1024);
      parser.body_limit(64 * 1024);
      parser.eager(true);
      boost::beast::error_code ec;
      parser.put(boost::asio::buffer(rest), ec);
      if (!ec && !parser.is_done()) parser.put_eof(ec);
      if (ec || !parser.is_header_done()) return 0;
      const auto& req = parser.get();
      ApiRequest api;
      api.method = std::string(req.method_string());
      api.target = std::string(req.target());
      api.authorization = req[http::field::authorization].empty() ? "Bearer " + (as_admin ? w.admin : w.trainee)
                                                                  : std::string(req[http::field::authorization]);
      api.accept_encoding = std::string(req[http::field::accept_encoding]);
      api.body = req.body();
      api.remote_address = "fuzz";
      check(w.core->api().handle(api));
      break;
    }
    case 1: {
      static const char* const kTargets[][2] = {{"POST", "/api/v1/login"},       {"POST", "/api/v1/users"},
                                                {"PATCH", "/api/v1/users/alice"}, {"POST", "/api/v1/cases"},
                                                {"POST", "/api/v1/assignments"},  {"POST", "/api/v1/me/password"},
                                                {"POST", "/api/v1/results"}};
      const auto& t = kTargets[(data[1] & 0x7f) % (sizeof kTargets / sizeof kTargets[0])];
      // Never lock the admin out: the fuzzer may not change root's account.
      if (std::string(t[0]) == "PATCH" || std::string(t[1]) == "/api/v1/me/password") {
        check(call(w, t[0], t[1], rest, false));
      } else {
        check(call(w, t[0], t[1], rest, as_admin));
      }
      break;
    }
    case 2: {
      const Status s = w.core->live().message(*w.publisher, rest);
      if (!s && (s.error().status >= 500 || s.error().message.empty())) std::abort();
      w.publisher->ended = false;
      break;
    }
    case 3: {
      const auto parsed = parse_watch_message(rest);
      if (!parsed && parsed.error().message.empty()) std::abort();
      break;
    }
    default:
      check(call(w, "GET", rest, "", as_admin));
      break;
  }
  return 0;
}
