#pragma once
// A real cathbox-server in this process (ServerApp on a free loopback port) over one backend,
// with light Argon2 parameters and the FakeRecords checker, plus helpers to talk to it.
#include <memory>
#include <optional>
#include <string>

#include "server/client.hpp"
#include "server/server_app.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server::test {

struct ServerOptions {
  std::string web_root;              // default: a temporary folder with an index.html
  std::string db_url;                // default: a fresh database of the backend
  std::string instance;
  std::size_t watcher_queue = 64;
  int idle_timeout_s = 0;            // 0: the server's default
  std::size_t max_connections_per_address = 0;  // 0: the server's default
  int ws_recheck_s = 0;                          // 0: the server's default
  int ws_idle_timeout_s = 0;                     // 0: the server's default
  std::size_t max_websockets_per_account = 0;    // 0: the server's default
  // Virtual time: the server's clock, and WebSockets swept only when the test calls
  // app->http().sweep() (no timer), maintenance only when it calls app->maintain_once().
  Clock* clock = nullptr;
  int record_retention_days = 0;
  std::optional<TlsFiles> tls{};     // HTTPS (base_url() then says https://HOST:PORT)
  std::string url_host = "127.0.0.1";  // base_url()'s host (the server listens on 127.0.0.1)
};

class RunningServer {
 public:
  RunningServer(const std::string& backend, ServerOptions options = {});
  ~RunningServer();
  [[nodiscard]] std::string base_url() const;
  [[nodiscard]] std::uint16_t port() const { return app->port(); }
  // Creates an account (if new) and answers a token.
  std::string token_for(const std::string& name, Role role, const std::string& password = "password-123");

  std::string db_url;
  std::string web_root;
  std::string scheme = "http";
  std::string host = "127.0.0.1";
  std::unique_ptr<ServerApp> app;
};

// Sends raw bytes on a new TCP connection to 127.0.0.1:port and answers what comes back until
// the server closes or timeout_ms passes.
[[nodiscard]] std::string raw_exchange(std::uint16_t port, const std::string& bytes, int timeout_ms = 5000);

}  // namespace cathbox::server::test
