#pragma once
// What cathbox-server's files share (main.cpp: the options and main; server_serve.cpp: serving;
// server_admin.cpp: `cathbox-server admin ...`): the exit codes (host/server/README.md), the
// serving options and the admin subcommands.
#include <string>

#include <CLI/CLI.hpp>

#include "server/result.hpp"
#include "server/store.hpp"

namespace cathbox::server::server_main {

inline constexpr int kOk = 0, kFailure = 1, kBadInput = 2, kUnavailable = 3, kIncompatible = 4;

inline int exit_code_for(const Error& e) {
  if (e.status == 409) return kIncompatible;
  if (e.status == 503) return kUnavailable;
  return kBadInput;
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

// Serves until SIGINT or SIGTERM (SIGHUP rereads the TLS certificate); the exit code.
int serve(const std::string& url, const std::string& listen, const ServeOptions& so);

// `cathbox-server admin ...`: the subcommands and what they were given.
struct AdminArgs {
  // The subcommands (null until added).
  CLI::App *admin{}, *create{}, *list{}, *set_role{}, *set_password{}, *disable{}, *enable{};
  CLI::App *add_case{}, *migrate{}, *backup{}, *restore{}, *export_user{}, *delete_user{};
  std::string user, role, case_path, case_name, backup_file, export_dir;
};

void add_admin_commands(CLI::App& cli, AdminArgs& a);

// The admin command given, on the store at `url`.
int run_admin(const AdminArgs& a, const std::string& url, const std::string& cache);

}  // namespace cathbox::server::server_main
