// `cathbox-server admin ...`: the subcommands (accounts, the case library, migrate, backup and
// restore, a user's data exported or deleted) on the store at --db.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "server/backup.hpp"
#include "server/case_library.hpp"
#include "server/clock.hpp"
#include "server/migrations.hpp"
#include "server/password_hasher.hpp"
#include "server/user_delete.hpp"
#include "server/user_export.hpp"
#include "server_main.hpp"

namespace cathbox::server::server_main {
namespace {

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

// create-user, set-role, set-password, disable, enable: the account commands.
int run_account_command(Store& store, SystemClock& clock, const AdminArgs& a) {
  std::optional<Role> parsed_role;
  if (!a.role.empty()) {
    parsed_role = parse_role(a.role);
    if (!parsed_role) {
      std::cerr << "cathbox-server: role '" << a.role << "': expected trainee, instructor or admin\n";
      return kBadInput;
    }
  }
  Auth auth(store, clock, PasswordHasher());
  if (a.create->parsed()) {
    Result<User> made = auth.create_user(a.user, *parsed_role, read_password());
    if (!made) {
      std::cerr << "cathbox-server: " << made.error().message << '\n';
      return made.error().status == 409 ? kFailure : kBadInput;
    }
    std::printf("created %s (%s)\n", a.user.c_str(), a.role.c_str());
    return kOk;
  }
  const std::optional<User> found = store.user_by_name(a.user);
  if (!found) {
    std::cerr << "cathbox-server: no user '" << a.user << "'\n";
    return kFailure;
  }
  if (a.set_role->parsed()) {
    (void)store.update_user(found->id, parsed_role, std::nullopt, std::nullopt);
  } else if (a.set_password->parsed()) {
    if (Status s = auth.set_password(found->id, read_password()); !s) {
      std::cerr << "cathbox-server: " << s.error().message << '\n';
      return kBadInput;
    }
  } else if (a.disable->parsed() || a.enable->parsed()) {
    (void)store.update_user(found->id, std::nullopt, std::nullopt, a.disable->parsed());
    if (a.disable->parsed()) store.delete_user_tokens(found->id);
  }
  std::printf("updated %s\n", a.user.c_str());
  return kOk;
}

}  // namespace

void add_admin_commands(CLI::App& cli, AdminArgs& a) {
  a.admin = cli.add_subcommand("admin", "accounts and the case library (uses --db / --data like the server)");
  a.admin->require_subcommand(1);
  // A subcommand that names an account.
  const auto on_user = [&a](const char* name, const char* what) {
    CLI::App* c = a.admin->add_subcommand(name, what);
    c->add_option("NAME", a.user)->required();
    return c;
  };
  a.create = on_user("create-user", "create an account (password: $CATHBOX_PASSWORD or one line on stdin)");
  a.create->add_option("--role", a.role, "trainee, instructor or admin")->required();
  a.list = a.admin->add_subcommand("list-users", "list accounts");
  a.set_role = on_user("set-role", "change an account's role");
  a.set_role->add_option("ROLE", a.role)->required();
  a.set_password = on_user("set-password", "change a password (as create-user) and end its sessions");
  a.disable = on_user("disable", "disable an account and end its sessions");
  a.enable = on_user("enable", "enable an account");
  a.add_case = a.admin->add_subcommand("add-case", "add a case file (and the HCLM it names) to the library");
  a.add_case->add_option("CASE", a.case_path)->required();
  a.add_case->add_option("--name", a.case_name, "library name (default: the file's stem)");
  a.migrate = a.admin->add_subcommand("migrate", "apply schema migrations and print the version");
  a.backup = a.admin->add_subcommand("backup", "write a consistent copy of the database to FILE, while it serves");
  a.backup->add_option("FILE", a.backup_file)->required();
  a.restore = a.admin->add_subcommand("restore", "restore FILE (from admin backup) into an empty --db");
  a.restore->add_option("FILE", a.backup_file)->required();
  a.export_user = on_user("export-user", "write an account's data (no password hash), results and records into DIR (new or empty)");
  a.export_user->add_option("DIR", a.export_dir)->required();
  a.delete_user = on_user("delete-user", "delete an account and all its data (results, records, traces) with the server STOPPED; running: DELETE /api/v1/users/NAME");
}

// The admin command given, on the store at `url`.
int run_admin(const AdminArgs& a, const std::string& url, const std::string& cache) {
  // Before the store is opened: a restore needs its target empty, a backup copies it as it is.
  if (a.backup->parsed() || a.restore->parsed()) return backup_or_restore(a.backup->parsed(), url, a.backup_file);
  int code = kOk;
  std::unique_ptr<Store> store = open_store(url, code);
  if (!store) return code;
  SystemClock clock;
  try {
    if (a.migrate->parsed()) {
      std::printf("%s: schema version %d\n", store->database().describe().c_str(), schema_version(store->database()));
      return kOk;
    }
    if (a.list->parsed()) {
      for (const User& u : store->list_users()) {
        std::printf("%-24s %-10s%s\n", u.name.c_str(), std::string(role_name(u.role)).c_str(), u.disabled ? " (disabled)" : "");
      }
      return kOk;
    }
    if (a.add_case->parsed()) return upload_case_file(*store, clock, a.case_path, a.case_name);
    if (a.export_user->parsed()) return export_user_data(*store, clock, a.user, a.export_dir);
    if (a.delete_user->parsed()) return delete_user_command(*store, clock, a.user, cache);
    return run_account_command(*store, clock, a);
  } catch (const StoreError& e) {
    std::cerr << "cathbox-server: " << e.what() << '\n';
    return kUnavailable;
  }
}

}  // namespace cathbox::server::server_main
