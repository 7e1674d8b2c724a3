// cathbox-server: the training centre's server, and `cathbox-server admin ...` for accounts
// and the case library. Exit codes (host/server/README.md): 0 ok, 1 failure, 2 bad input,
// 3 database or address unavailable, 4 database schema newer than this program.
#include <signal.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include <CLI/CLI.hpp>

#include "server/backup.hpp"
#include "server/case_library.hpp"
#include "server/clock.hpp"
#include "server/log_line.hpp"
#include "server/migrations.hpp"
#include "server/password_hasher.hpp"
#include "server/server_app.hpp"
#include "server/store.hpp"
#include "server/user_delete.hpp"
#include "server/user_export.hpp"

namespace {

using namespace cathbox::server;

constexpr int kOk = 0, kFailure = 1, kBadInput = 2, kUnavailable = 3, kIncompatible = 4;

int exit_code_for(const Error& e) {
  if (e.status == 409) return kIncompatible;
  if (e.status == 503) return kUnavailable;
  return kBadInput;
}

std::string default_data_dir() {
  if (const char* xdg = std::getenv("XDG_DATA_HOME"); xdg != nullptr && xdg[0] == '/') return std::string(xdg) + "/cathbox";
  if (const char* home = std::getenv("HOME"); home != nullptr && home[0] != '\0') return std::string(home) + "/.local/share/cathbox";
  return "/var/lib/cathbox";
}

std::string db_url(const std::string& given, const std::string& data_dir) {
  return given.empty() ? "sqlite:" + data_dir + "/server.db" : given;
}

// A password from the CATHBOX_PASSWORD variable, else the first line of standard input.
std::string read_password() {
  if (const char* env = std::getenv("CATHBOX_PASSWORD"); env != nullptr) return env;
  if (isatty(0)) std::cerr << "password: " << std::flush;
  std::string line;
  std::getline(std::cin, line);
  if (!line.empty() && line.back() == '\r') line.pop_back();
  return line;
}

struct Admin {
  std::unique_ptr<Store> store;
  SystemClock clock;
};

// Opens and migrates the store for an admin command; prints the problem and sets `code`.
std::unique_ptr<Store> open_store(const std::string& url, int& code) {
  DatabaseOpen opened = open_database(url);
  if (!opened.db) {
    std::cerr << "cathbox-server: " << opened.error << '\n';
    code = opened.error.rfind("--db: unknown", 0) == 0 ? kBadInput : kUnavailable;
    return nullptr;
  }
  try {
    Result<MigrationReport> m = migrate(*opened.db);
    if (!m) {
      std::cerr << "cathbox-server: " << m.error().message << '\n';
      code = exit_code_for(m.error());
      return nullptr;
    }
  } catch (const StoreError& e) {
    std::cerr << "cathbox-server: " << e.what() << '\n';
    code = kUnavailable;
    return nullptr;
  }
  return std::make_unique<Store>(std::move(opened.db));
}

struct ServeOptions {
  std::string web;
  std::string wasm;  // cathbox-trainee.js/.wasm/.worker.js for /train.html, served at /wasm/
  std::string cache;  // DATA/cache: browser meshes and debrief traces (zstd), rebuilt when missing
  std::string instance;
  int io_threads = 2;
  int api_threads = 4;
  double token_hours = 12.0;
  int login_burst = 20;
  double logins_per_minute = 30.0;
  std::string tls_cert;
  std::string tls_key;
  bool insecure_http = false;
  std::string log_format = "text";
  int record_retention_days = 0;
};

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

std::string read_file(const std::string& path, bool& ok) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  ok = static_cast<bool>(in) || in.eof();
  return ss.str();
}

int upload_case_file(Store& store, SystemClock& clock, const std::string& case_path, std::string name) {
  bool ok = false;
  CaseBundle b;
  b.case_text = read_file(case_path, ok);
  if (!ok) {
    std::cerr << "cathbox-server: " << case_path << ": cannot read\n";
    return kBadInput;
  }
  const std::filesystem::path p(case_path);
  b.case_file = p.filename().string();
  if (name.empty()) name = p.stem().string();
  // The case's vessel file (and its own wall, `surface FILE`) sit next to it; find their names by
  // parsing the case.
  std::string vessel;
  std::string surface;
  std::istringstream lines(b.case_text);
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string key;
    if (words >> key && key == "vessel") words >> vessel;
    if (key == "surface") words >> surface;
  }
  // A file the case names, read from beside it: its file name and contents, or false (one line).
  const auto read_beside = [&](const std::string& named, std::string& file, std::string& contents) {
    if (named.empty()) return true;
    const std::filesystem::path at = p.parent_path() / named;
    file = std::filesystem::path(named).filename().string();
    contents = read_file(at.string(), ok);
    if (!ok) std::cerr << "cathbox-server: " << at.string() << ": cannot read\n";
    return ok;
  };
  if (!read_beside(surface, b.surface_file, b.surface_bytes)) return kBadInput;
  if (!read_beside(vessel, b.hclm_file, b.hclm_text)) return kBadInput;
  CaseLibrary library(store);
  Result<CaseUploadOutcome> up = library.upload(name, b, std::nullopt, clock.now_us());
  if (!up) {
    std::cerr << "cathbox-server: " << up.error().message << '\n';
    return kBadInput;
  }
  const CaseVersion& v = up.value().version;
  std::printf("%s version %d%s: %lld bytes raw, %lld on the wire, level-2 mesh %lld vertices / %lld triangles = %lld bytes (%.1fx)\n",
              v.name.c_str(), v.version, up.value().created ? "" : " (unchanged)", static_cast<long long>(v.raw_bytes),
              static_cast<long long>(v.wire_bytes), static_cast<long long>(v.mesh_vertices), static_cast<long long>(v.mesh_triangles),
              static_cast<long long>(v.mesh_bytes), v.wire_bytes > 0 ? static_cast<double>(v.mesh_bytes) / static_cast<double>(v.wire_bytes) : 0.0);
  return kOk;
}

// `admin backup FILE` or `admin restore FILE`.
int backup_or_restore(bool backup, const std::string& url, const std::string& file) {
  const Status done = backup ? backup_database(url, file) : restore_database(url, file);
  if (!done) {
    std::cerr << "cathbox-server: " << done.error().message << '\n';
    return exit_code_for(done.error());
  }
  std::printf("%s %s\n", backup ? "backed up to" : "restored from", file.c_str());
  return kOk;
}

// The login running an admin command, for its audit row.
std::string cli_actor() {
  const char* login = std::getenv("USER");
  return login != nullptr && login[0] != '\0' ? login : "cli";
}

// `admin export-user`: 1 when there is no such user, 2 when DIR is not a new or empty folder.
int export_user_data(Store& store, SystemClock& clock, const std::string& name, const std::string& dir) {
  Result<UserExport> done = export_user(store, name, dir, cli_actor(), clock.now_us());
  if (!done) {
    std::cerr << "cathbox-server: " << done.error().message << '\n';
    return done.error().status == 404 ? kFailure : kBadInput;
  }
  std::printf("exported %s to %s: %d results, %d files, %lld bytes\n", name.c_str(), dir.c_str(), done.value().results, done.value().files,
              static_cast<long long>(done.value().bytes));
  return kOk;
}

// `admin delete-user`, for a stopped server (a running one is asked through DELETE
// /api/v1/users/NAME, which also empties its memory cache and ends the live streams): 1 when there
// is no such user or it is the last admin.
int delete_user_command(Store& store, SystemClock& clock, const std::string& name, const std::string& cache_dir) {
  ArtifactCache cache;
  cache.keep_on_disk(cache_dir);
  Result<UserDeletion> done = delete_user_data(store, &cache, nullptr, name, {0, clock.now_us(), cli_actor(), "", "", "", "cli"});
  if (!done) {
    std::cerr << "cathbox-server: " << done.error().message << '\n';
    return kFailure;
  }
  std::printf("deleted %s: %d results with their records\n", name.c_str(), done.value().results);
  return kOk;
}

}  // namespace

// NOLINTNEXTLINE(readability-function-size): main declares the command line, a flat list of subcommands and their options, then dispatches.
int main(int argc, char** argv) {
  CLI::App cli{"cathbox-server: cases, assignments, results and live sessions for a training centre"};
  cli.require_subcommand(0, 1);
  std::string db, listen = "127.0.0.1:8080", data = default_data_dir();
  ServeOptions so;
  so.web = CATHBOX_SERVER_WEB_DIR;
  cli.add_option("--db", db, "sqlite:PATH or postgresql://... (default: sqlite:DATA/server.db)");
  cli.add_option("--listen", listen, "HOST:PORT to listen on (port 0: any free port)")->capture_default_str();
  cli.add_option("--data", data, "data folder (default: $XDG_DATA_HOME/cathbox)")->capture_default_str();
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

  CLI::App* admin = cli.add_subcommand("admin", "accounts and the case library (uses --db / --data like the server)");
  admin->require_subcommand(1);
  std::string user, role, case_path, case_name;
  CLI::App* create = admin->add_subcommand("create-user", "create an account (password: $CATHBOX_PASSWORD or one line on stdin)");
  create->add_option("NAME", user)->required();
  create->add_option("--role", role, "trainee, instructor or admin")->required();
  CLI::App* list = admin->add_subcommand("list-users", "list accounts");
  CLI::App* set_role = admin->add_subcommand("set-role", "change an account's role");
  set_role->add_option("NAME", user)->required();
  set_role->add_option("ROLE", role)->required();
  CLI::App* set_password = admin->add_subcommand("set-password", "change a password (as create-user) and end its sessions");
  set_password->add_option("NAME", user)->required();
  CLI::App* disable = admin->add_subcommand("disable", "disable an account and end its sessions");
  disable->add_option("NAME", user)->required();
  CLI::App* enable = admin->add_subcommand("enable", "enable an account");
  enable->add_option("NAME", user)->required();
  CLI::App* add_case = admin->add_subcommand("add-case", "add a case file (and the HCLM it names) to the library");
  add_case->add_option("CASE", case_path)->required();
  add_case->add_option("--name", case_name, "library name (default: the file's stem)");
  CLI::App* migrate_cmd = admin->add_subcommand("migrate", "apply schema migrations and print the version");
  std::string backup_file;
  CLI::App* backup_cmd = admin->add_subcommand("backup", "write a consistent copy of the database to FILE, while it serves");
  backup_cmd->add_option("FILE", backup_file)->required();
  CLI::App* restore_cmd = admin->add_subcommand("restore", "restore FILE (from admin backup) into an empty --db");
  restore_cmd->add_option("FILE", backup_file)->required();
  std::string export_dir;
  CLI::App* export_cmd = admin->add_subcommand("export-user", "write an account's data (no password hash), results and records into DIR (new or empty)");
  export_cmd->add_option("NAME", user)->required();
  export_cmd->add_option("DIR", export_dir)->required();
  CLI::App* delete_cmd = admin->add_subcommand(
      "delete-user", "delete an account and all its data (results, records, traces) with the server STOPPED; running: DELETE /api/v1/users/NAME");
  delete_cmd->add_option("NAME", user)->required();

  try {
    cli.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int rc = cli.exit(e);
    return rc == 0 ? kOk : kBadInput;
  }
  const std::string url = db_url(db, data);
  so.cache = data + "/cache";
  if (!admin->parsed()) return serve(url, listen, so);
  // Before the store is opened: a restore needs its target empty, a backup copies it as it is.
  if (backup_cmd->parsed() || restore_cmd->parsed()) return backup_or_restore(backup_cmd->parsed(), url, backup_file);

  int code = kOk;
  std::unique_ptr<Store> store = open_store(url, code);
  if (!store) return code;
  SystemClock clock;
  try {
    if (migrate_cmd->parsed()) {
      std::printf("%s: schema version %d\n", store->database().describe().c_str(), schema_version(store->database()));
      return kOk;
    }
    if (list->parsed()) {
      for (const User& u : store->list_users()) {
        std::printf("%-24s %-10s%s\n", u.name.c_str(), std::string(role_name(u.role)).c_str(), u.disabled ? " (disabled)" : "");
      }
      return kOk;
    }
    if (add_case->parsed()) return upload_case_file(*store, clock, case_path, case_name);
    if (export_cmd->parsed()) return export_user_data(*store, clock, user, export_dir);
    if (delete_cmd->parsed()) return delete_user_command(*store, clock, user, so.cache);
    std::optional<Role> parsed_role;
    if (!role.empty()) {
      parsed_role = parse_role(role);
      if (!parsed_role) {
        std::cerr << "cathbox-server: role '" << role << "': expected trainee, instructor or admin\n";
        return kBadInput;
      }
    }
    Auth auth(*store, clock, PasswordHasher());
    if (create->parsed()) {
      Result<User> made = auth.create_user(user, *parsed_role, read_password());
      if (!made) {
        std::cerr << "cathbox-server: " << made.error().message << '\n';
        return made.error().status == 409 ? kFailure : kBadInput;
      }
      std::printf("created %s (%s)\n", user.c_str(), role.c_str());
      return kOk;
    }
    const std::optional<User> found = store->user_by_name(user);
    if (!found) {
      std::cerr << "cathbox-server: no user '" << user << "'\n";
      return kFailure;
    }
    if (set_role->parsed()) {
      (void)store->update_user(found->id, parsed_role, std::nullopt, std::nullopt);
    } else if (set_password->parsed()) {
      if (Status s = auth.set_password(found->id, read_password()); !s) {
        std::cerr << "cathbox-server: " << s.error().message << '\n';
        return kBadInput;
      }
    } else if (disable->parsed() || enable->parsed()) {
      (void)store->update_user(found->id, std::nullopt, std::nullopt, disable->parsed());
      if (disable->parsed()) store->delete_user_tokens(found->id);
    }
    std::printf("updated %s\n", user.c_str());
    return kOk;
  } catch (const StoreError& e) {
    std::cerr << "cathbox-server: " << e.what() << '\n';
    return kUnavailable;
  }
}
