// cathbox-server: the training centre's server, and `cathbox-server admin ...` for accounts
// and the case library. Exit codes (host/server/README.md): 0 ok, 1 failure, 2 bad input,
// 3 database or address unavailable, 4 database schema newer than this program. Here the options
// and main; serving in server_serve.cpp, the admin commands in server_admin.cpp.
#include <cstdlib>
#include <string>

#include <CLI/CLI.hpp>

#include "server_main.hpp"

namespace {

using namespace cathbox::server;
using namespace cathbox::server::server_main;

std::string default_data_dir() {
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg != nullptr && xdg[0] == '/') return std::string(xdg) + "/cathbox";
  if (const char* home = std::getenv("HOME"); home != nullptr && home[0] != '\0') return std::string(home) + "/.local/share/cathbox";
  return "/var/lib/cathbox";
}

std::string db_url(const std::string& given, const std::string& data_dir) {
  return given.empty() ? "sqlite:" + data_dir + "/server.db" : given;
}
// The server's own options (serving; the admin commands read --db and --data too).
struct ServerArgs {
  std::string db;
  std::string listen = "127.0.0.1:8080";
  std::string data = default_data_dir();
  ServeOptions so;
};

void add_server_options(CLI::App& cli, ServerArgs& a) {
  ServeOptions& so = a.so;
  so.web = CATHBOX_SERVER_WEB_DIR;
  cli.add_option("--db", a.db, "sqlite:PATH or postgresql://... (default: sqlite:DATA/server.db)");
  cli.add_option("--listen", a.listen, "HOST:PORT to listen on (port 0: any free port)")->capture_default_str();
  cli.add_option("--data", a.data, "data folder (default: $XDG_DATA_HOME/cathbox)")->capture_default_str();
  cli.add_option("--web", so.web, "folder of the browser pages")->capture_default_str();
  cli.add_option("--wasm", so.wasm, "folder of the trainee page's WebAssembly session (scripts/wasm-build DIR cathbox-trainee: DIR/bin), served at /wasm/");
  cli.add_option("--instance", so.instance, "this instance's name (default: random)");
  cli.add_option("--io-threads", so.io_threads, "socket threads")->check(CLI::Range(1, 64))->capture_default_str();
  cli.add_option("--api-threads", so.api_threads, "API handler threads")->check(CLI::Range(1, 256))->capture_default_str();
  cli.add_option("--token-hours", so.token_hours, "bearer token lifetime")->check(CLI::Range(0.01, 24.0 * 365))->capture_default_str();
  cli.add_option("--tls-cert", so.tls_cert, "PEM certificate chain: serve HTTPS and wss:// (reread on SIGHUP)");
  cli.add_option("--tls-key", so.tls_key, "PEM private key of --tls-cert");
  cli.add_option("--log-format", so.log_format, "text, or json: one JSON object a line (time, level, msg, fields)")->capture_default_str();
  cli.add_flag("--insecure-http", so.insecure_http, "allow plain HTTP on a non-loopback --listen (only behind a TLS proxy)");
  cli.add_option("--record-retention-days", so.record_retention_days,
                 "session records uploaded more than N days ago are removed (results stay, marked); 0: kept forever")
      ->check(CLI::Range(0, 36500))
      ->capture_default_str();
  cli.add_option("--login-burst", so.login_burst, "login attempts one address may make at once")->check(CLI::Range(1, 1000000))->capture_default_str();
  cli.add_option("--logins-per-minute", so.logins_per_minute, "login attempts per minute one address gets back")
      ->check(CLI::Range(0.1, 1e6))
      ->capture_default_str();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App cli{"cathbox-server: cases, assignments, results and live sessions for a training centre"};
  cli.require_subcommand(0, 1);
  ServerArgs server;
  add_server_options(cli, server);
  AdminArgs admin;
  add_admin_commands(cli, admin);
  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? kOk : kBadInput;
  }
  const std::string url = db_url(server.db, server.data);
  server.so.cache = server.data + "/cache";
  if (!admin.admin->parsed()) return serve(url, server.listen, server.so);
  return run_admin(admin, url, server.so.cache);
}
