// cathbox-server's serving: the log lines, the server started on the store at the URL, and the
// signals that reload its certificate or stop it.
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <string>

#include "server/clock.hpp"
#include "server/log_line.hpp"
#include "server/server_app.hpp"
#include "server_main.hpp"

namespace cathbox::server::server_main {
namespace {

// The serving program's lines: info and warnings on standard output, errors on standard error,
// as text or one JSON object a line (--log-format).
struct Say {
  LogFormat format = LogFormat::kText;
  SystemClock clock;
  void operator()(std::string_view level, const std::string& message, const LogFields& fields = {}) {
    std::FILE* to = level == "error" ? stderr : stdout;
    std::fprintf(to, "%s\n", log_line(format, level, message, clock.now_us(), fields).c_str());
    std::fflush(to);
  }
};

}  // namespace

int serve(const std::string& url, const std::string& listen, const ServeOptions& so) {
  Say say;
  if (const std::optional<LogFormat> f = parse_log_format(so.log_format)) {
    say.format = *f;
  } else {
    say("error", "--log-format: '" + so.log_format + "': expected text or json");
    return kBadInput;
  }
  ServerConfig config;
  config.db_url = url;
  const std::size_t colon = listen.rfind(':');
  if (colon == std::string::npos) {
    say("error", "--listen: expected HOST:PORT, got '" + listen + "'");
    return kBadInput;
  }
  config.http.host = listen.substr(0, colon);
  if (config.http.host.size() > 2 && config.http.host.front() == '[' && config.http.host.back() == ']') {
    config.http.host = config.http.host.substr(1, config.http.host.size() - 2);
  }
  try {
    const int port = std::stoi(listen.substr(colon + 1));
    if (port < 0 || port > 65535) throw std::out_of_range("port");
    config.http.port = static_cast<std::uint16_t>(port);
  } catch (const std::exception&) {
    say("error", "--listen: '" + listen.substr(colon + 1) + "' is not a port");
    return kBadInput;
  }
  config.http.mounts = default_mounts(so.web);
  if (!so.wasm.empty()) config.http.mounts.push_back({"/wasm/", so.wasm});
  config.http.io_threads = so.io_threads;
  config.http.api_threads = so.api_threads;
  config.auth.token_lifetime_us = static_cast<std::int64_t>(so.token_hours * 3600e6);
  config.auth.address_burst = so.login_burst;
  config.auth.address_per_minute = so.logins_per_minute;
  config.instance = so.instance;
  config.cache_dir = so.cache;
  config.record_retention_days = so.record_retention_days;
  if (so.tls_cert.empty() != so.tls_key.empty()) {
    say("error", "--tls-cert and --tls-key go together");
    return kBadInput;
  }
  if (!so.tls_cert.empty()) config.http.tls = TlsFiles{so.tls_cert, so.tls_key};
  config.http.insecure_http = so.insecure_http;

  // The signals that stop the server are taken by this thread only (sigwait below).
  sigset_t stop_signals;
  sigemptyset(&stop_signals);
  sigaddset(&stop_signals, SIGINT);
  sigaddset(&stop_signals, SIGTERM);
  sigaddset(&stop_signals, SIGHUP);  // reload the TLS certificate
  pthread_sigmask(SIG_BLOCK, &stop_signals, nullptr);
  signal(SIGPIPE, SIG_IGN);

  Result<std::unique_ptr<ServerApp>> app = ServerApp::start(std::move(config));
  if (!app) {
    say("error", app.error().message);
    return exit_code_for(app.error());
  }
  ServerApp& a = *app.value();
  const bool tls = app.value()->http().tls();
  if (!tls && so.insecure_http) {
    say("warning", "--insecure-http: plain HTTP on " + listen + ", passwords and tokens cross the network in clear unless a TLS proxy is in front",
        {{"listen", listen}});
  }
  const std::string served = std::string(tls ? "https" : "http") + "://" + listen.substr(0, colon) + ":" + std::to_string(a.port());
  say("info", "listening on " + served + " (" + a.describe_db() + ", schema " + std::to_string(a.schema_version()) + ", instance " + a.instance() + ")",
      {{"url", served}, {"db", a.describe_db()}, {"schema", std::to_string(a.schema_version())}, {"instance", a.instance()}});
  int sig = 0;
  while (sigwait(&stop_signals, &sig) == 0 && sig == SIGHUP) {
    const Status reloaded = app.value()->http().reload_tls();
    if (reloaded) {
      say("info", "TLS certificate reloaded from " + so.tls_cert, {{"cert", so.tls_cert}});
    } else {
      say("warning", "SIGHUP: " + reloaded.error().message + " (the old certificate stays)");
    }
  }
  say("info", "stopping (signal " + std::to_string(sig) + ")", {{"signal", std::to_string(sig)}});
  app.value()->stop();
  return kOk;
}

}  // namespace cathbox::server::server_main
