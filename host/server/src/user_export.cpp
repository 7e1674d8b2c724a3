#include "server/user_export.hpp"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/audit_log.hpp"
#include "server/sha256.hpp"

namespace cathbox::server {

namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json optional_json(const std::optional<std::int64_t>& v) { return v ? json(*v) : json(nullptr); }

json parsed_or_text(const std::string& text) {
  json parsed = json::parse(text, nullptr, false);
  return parsed.is_discarded() ? json(text) : parsed;  // kept as stored when it is not JSON
}

// The files written so far, for the manifest.
class Folder {
 public:
  explicit Folder(fs::path dir) : dir_(std::move(dir)) {}

  Status write(const std::string& relative, const std::string& bytes) {
    const fs::path path = dir_ / relative;
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) return make_error(400, path.string() + ": cannot write: " + std::strerror(errno));
    manifest_.push_back({{"path", relative}, {"bytes", bytes.size()}, {"sha256", sha256_hex(bytes)}});
    total_bytes_ += static_cast<std::int64_t>(bytes.size());
    return Ok{};
  }
  Status write_json(const std::string& relative, const json& value) { return write(relative, value.dump(2) + "\n"); }
  [[nodiscard]] const json& manifest() const { return manifest_; }
  [[nodiscard]] std::int64_t total_bytes() const { return total_bytes_; }

 private:
  fs::path dir_;
  json manifest_ = json::array();
  std::int64_t total_bytes_ = 0;
};

Status prepare_folder(const std::string& dir) {
  std::error_code ec;
  if (fs::exists(dir, ec)) {
    if (!fs::is_directory(dir, ec)) return make_error(400, dir + ": exists and is not a folder; an export goes into a new or empty folder");
    if (!fs::is_empty(dir, ec)) return make_error(400, dir + ": not empty; an export goes into a new or empty folder");
  }
  fs::create_directories(fs::path(dir) / "records", ec);
  if (ec) return make_error(400, dir + ": cannot write: " + ec.message());
  return Ok{};
}

json user_json(const User& u) {
  return {{"id", u.id}, {"name", u.name}, {"role", role_name(u.role)}, {"disabled", u.disabled}, {"created_us", u.created_us}};
}

json assignments_json(Store& store, std::int64_t user_id) {
  json out = json::array();
  for (const Assignment& a : store.list_assignments(user_id)) {
    out.push_back({{"id", a.id}, {"case", a.case_name}, {"case_version", a.case_version}, {"criteria", parsed_or_text(a.criteria_json)},
                   {"note", a.note}, {"assigned_by", optional_json(a.assigned_by)}, {"created_us", a.created_us},
                   {"due_us", optional_json(a.due_us)}});
  }
  return out;
}

// Every result of the user, oldest first (list_results answers pages, newest first).
std::vector<ResultRow> all_results(Store& store, std::int64_t user_id) {
  std::vector<ResultRow> rows;
  ResultFilter f;
  f.user_id = user_id;
  f.limit = 500;
  for (;;) {
    std::vector<ResultRow> page = store.list_results(f);
    rows.insert(rows.end(), page.begin(), page.end());
    if (static_cast<int>(page.size()) < f.limit) break;
    f.offset += f.limit;
  }
  return {rows.rbegin(), rows.rend()};
}

json audit_json(Database& db, const std::string& name) {
  json out = json::array();
  db.transact(TxMode::kRead, [&](SqlSession& s) {
    out = json::array();
    // Rows they made, rows naming them, and assignments made for them ("trainee=NAME case=...").
    const std::string for_them = "trainee=" + name + " ";
    for (const SqlRow& r : s.query("SELECT id, at_us, actor, action, target, detail, remote FROM audit_log "
                                   "WHERE actor = $1 OR target = $1 OR detail LIKE 'trainee=%' ORDER BY at_us, id",
                                   {name})) {
      if (r.text(2) != name && r.text(4) != name && r.text(5).rfind(for_them, 0) != 0) continue;
      out.push_back({{"id", r.integer(0)}, {"at_us", r.integer(1)}, {"actor", r.text(2)}, {"action", r.text(3)},
                     {"target", r.text(4)}, {"detail", r.text(5)}, {"remote", r.text(6)}});
    }
  });
  return out;
}

}  // namespace

Result<UserExport> export_user(Store& store, const std::string& name, const std::string& dir, const std::string& actor,
                               std::int64_t now_us) {
  const std::optional<User> user = store.user_by_name(name);
  if (!user) return make_error(404, "no user '" + name + "'");
  if (Status s = prepare_folder(dir); !s) return s.error();
  append_audit(store.database(), {0, now_us, actor, "user.export", name, "to " + dir, "cli"});

  Folder folder(dir);
  UserExport done;
  json results = json::array();
  for (const ResultRow& r : all_results(store, user->id)) {
    const std::optional<std::string> record = store.result_record(r.id);
    if (!record && !r.record_gone_us) continue;  // deleted since the list was read
    // A record the retention setting removed: the result without it ("record": null).
    const std::string file = record ? "records/" + std::to_string(r.id) + ".cbxrec" : "";
    if (record) {
      if (Status s = folder.write(file, *record); !s) return s.error();
    }
    json metrics = json::object();
    for (const MetricValue& m : store.result_metrics(r.id)) metrics[m.name] = m.value;
    results.push_back({{"id", r.id}, {"record", record ? json(file) : json(nullptr)},
                       {"record_gone_us", optional_json(r.record_gone_us)}, {"content_hash", r.content_hash}, {"run_hash", r.run_hash},
                       {"complete", r.complete}, {"assignment_id", optional_json(r.assignment_id)}, {"case", r.case_name},
                       {"case_version_id", optional_json(r.case_version_id)}, {"started_us", r.started_us},
                       {"duration_ms", r.duration_ms}, {"uploaded_us", r.uploaded_us}, {"record_bytes", r.record_bytes},
                       {"passed", r.passed ? json(*r.passed) : json(nullptr)}, {"metrics", metrics}});
    ++done.results;
  }
  const std::pair<const char*, json> parts[] = {{"user.json", user_json(*user)},
                                                 {"assignments.json", assignments_json(store, user->id)},
                                                 {"results.json", std::move(results)},
                                                 {"audit.json", audit_json(store.database(), name)}};
  for (const auto& [file, value] : parts) {
    if (Status s = folder.write_json(file, value); !s) return s.error();
  }
  const json manifest{{"user", name}, {"exported_us", now_us}, {"files", folder.manifest()}};
  done.files = static_cast<int>(folder.manifest().size());
  done.bytes = folder.total_bytes();
  if (Status s = folder.write_json("manifest.json", manifest); !s) return s.error();
  return done;
}

}  // namespace cathbox::server
