#include "support/server_fixture.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <fstream>

namespace cathbox::server::test {

RunningServer::RunningServer(const std::string& backend, ServerOptions options) {
  db_url = options.db_url.empty() ? fresh_database_url(backend) : options.db_url;
  web_root = options.web_root;
  if (web_root.empty()) {
    web_root = temp_folder();
    std::ofstream(web_root + "/index.html") << "<!doctype html><title>cathbox</title>\n";
    std::ofstream(web_root + "/.secret") << "hidden\n";
  }
  ServerConfig config;
  config.db_url = db_url;
  config.http.host = "127.0.0.1";
  config.http.tls = options.tls;
  if (options.tls) scheme = "https";
  host = options.url_host;
  config.http.port = 0;
  config.http.mounts = default_mounts(web_root);
  config.http.watcher_queue = options.watcher_queue;
  if (options.idle_timeout_s > 0) config.http.idle_timeout_s = options.idle_timeout_s;
  if (options.ws_recheck_s > 0) config.http.ws_recheck_s = options.ws_recheck_s;
  if (options.max_connections_per_address > 0) config.http.max_connections_per_address = options.max_connections_per_address;
  if (options.ws_idle_timeout_s > 0) config.http.ws_idle_timeout_s = options.ws_idle_timeout_s;
  if (options.max_websockets_per_account > 0) config.http.max_websockets_per_account = options.max_websockets_per_account;
  if (options.clock != nullptr) {
    config.clock = options.clock;
    config.http.sweep_every_ms = 0;
    config.maintenance_every_s = 0;
  }
  config.record_retention_days = options.record_retention_days;
  config.argon2 = test_argon2_params();
  config.instance = options.instance;
  config.checker = std::make_unique<FakeRecords>();
  Result<std::unique_ptr<ServerApp>> started = ServerApp::start(std::move(config));
  if (!started) throw std::runtime_error(started.error().message);
  app = std::move(started.value());
}

RunningServer::~RunningServer() {
  if (app) app->stop();
}

std::string RunningServer::base_url() const { return scheme + "://" + host + ":" + std::to_string(app->port()); }

std::string RunningServer::token_for(const std::string& name, Role role, const std::string& password) {
  if (!app->store().user_by_name(name)) (void)app->auth().create_user(name, role, password);
  ServerClient client(base_url());
  const Status s = client.login(name, password);
  if (!s) throw std::runtime_error("login " + name + ": " + s.error().message);
  return client.token();
}

std::string raw_exchange(std::uint16_t port, const std::string& bytes, int timeout_ms) {
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(port);
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (::connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    ::close(fd);
    return "";
  }
  std::size_t sent = 0;
  while (sent < bytes.size()) {
    const ssize_t n = ::send(fd, bytes.data() + sent, bytes.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) break;  // the server may answer and close before reading everything
    sent += static_cast<std::size_t>(n);
  }
  ::shutdown(fd, SHUT_WR);
  std::string out;
  for (;;) {
    pollfd p{fd, POLLIN, 0};
    if (::poll(&p, 1, timeout_ms) <= 0) break;
    char buf[4096];
    const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
    if (n <= 0) break;
    out.append(buf, static_cast<std::size_t>(n));
  }
  ::close(fd);
  return out;
}

}  // namespace cathbox::server::test
