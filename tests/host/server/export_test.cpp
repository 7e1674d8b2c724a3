// A trainee's data export (`cathbox-server admin export-user`, a subject-access request) on
// SQLite and PostgreSQL: after a real record is uploaded against an assignment, the export holds
// the account without its password hash, the assignment, the result with its metrics, the record
// byte for byte as the server stores it, the audit rows about the trainee (the export's own
// among them), and a manifest whose sizes and SHA-256 match every file. Bad input: an unknown
// user and a folder that is not empty; neither writes anything nor logs an export. The program
// answers them with one line and exit 1 and 2.
#include <filesystem>
#include <fstream>

#include "server/audit_log.hpp"
#include "server/sha256.hpp"
#include "server/testing/child_process.hpp"
#include "server/user_export.hpp"
#include "record_files.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server::test {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

json read_json(const fs::path& path) { return json::parse(read_all(path.string())); }

int export_rows(ApiFixture& f) {
  int n = 0;
  for (const AuditEntry& e : audit_entries(f.store->database(), {})) n += e.action == "user.export" ? 1 : 0;
  return n;
}

class ExportTest : public ::testing::TestWithParam<std::string> {};

TEST_P(ExportTest, TheExportHoldsTheirDataAndRecordsByteForByteAndNoPasswordHash) {
  ApiFixture centre(GetParam(), make_session_checker());
  const std::string root = centre.user("root", Role::kAdmin);
  const std::string teacher = centre.user("teacher", Role::kInstructor);
  const std::string alice = centre.user("alice", Role::kTrainee);
  centre.user("bob", Role::kTrainee);
  ASSERT_EQ(centre.upload_bundled_case("y_bifurcation", "ybif", teacher).status, 201);
  const json a = centre.call_json("POST", "/api/v1/assignments",
                                  {{"trainee", "alice"}, {"case", "ybif"},
                                   {"criteria", json::array({{{"metric", "tip_path_mm"}, {"op", ">="}, {"value", 50}}})}},
                                  teacher, 201);
  centre.call_json("POST", "/api/v1/assignments", {{"trainee", "bob"}, {"case", "ybif"}}, teacher, 201);
  ASSERT_EQ(centre.call("PATCH", "/api/v1/users/bob", R"({"disabled":true})", root).status, 200);
  const std::string record = read_all(record_left_branch({}, "export_left.cbxrec"));
  const ApiResponse stored = centre.call("POST", "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>()), record, alice);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const std::int64_t result_id = json::parse(stored.body)["id"].get<std::int64_t>();

  const fs::path dir = fs::path(temp_folder()) / "alice-export";
  const Result<UserExport> done = export_user(*centre.store, "alice", dir.string(), "dpo", centre.clock.now_us());
  ASSERT_TRUE(done) << done.error().message;
  EXPECT_EQ(done.value().results, 1);
  EXPECT_EQ(done.value().files, 5);  // user, assignments, results, audit, one record (the manifest lists them)

  const json user = read_json(dir / "user.json");
  EXPECT_EQ(user["name"], "alice");
  EXPECT_EQ(user["role"], "trainee");
  EXPECT_FALSE(user.contains("password_hash"));
  const json assignments = read_json(dir / "assignments.json");
  ASSERT_EQ(assignments.size(), 1U);  // not bob's
  EXPECT_EQ(assignments[0]["id"], a["id"]);
  EXPECT_EQ(assignments[0]["criteria"][0]["metric"], "tip_path_mm");
  const json results = read_json(dir / "results.json");
  ASSERT_EQ(results.size(), 1U);
  EXPECT_EQ(results[0]["id"], result_id);
  EXPECT_EQ(results[0]["passed"], true);
  EXPECT_GE(results[0]["metrics"]["tip_path_mm"].get<double>(), 50.0);
  const std::optional<std::string> kept = centre.store->result_record(result_id);
  ASSERT_TRUE(kept);
  EXPECT_EQ(read_all((dir / results[0]["record"].get<std::string>()).string()), *kept);
  EXPECT_EQ(*kept, record);
  EXPECT_EQ(results[0]["content_hash"], sha256_hex(*kept));

  // The audit rows about alice: the assignment made for her and this export; bob's are not hers.
  const json audit = read_json(dir / "audit.json");
  ASSERT_EQ(audit.size(), 2U) << audit.dump();
  EXPECT_EQ(audit[0]["action"], "assignment.create");
  EXPECT_EQ(audit[1]["action"], "user.export");
  EXPECT_EQ(audit[1]["actor"], "dpo");
  EXPECT_EQ(audit[1]["remote"], "cli");
  const std::vector<AuditEntry> logged = audit_entries(centre.store->database(), {});
  ASSERT_FALSE(logged.empty());
  EXPECT_EQ(logged[0].action, "user.export");
  EXPECT_EQ(logged[0].target, "alice");

  // The manifest: every other file, its size and hash; no file anywhere holds a password hash.
  const json manifest = read_json(dir / "manifest.json");
  EXPECT_EQ(manifest["user"], "alice");
  int listed = 0;
  for (const json& f : manifest["files"]) {
    const std::string bytes = read_all((dir / f["path"].get<std::string>()).string());
    EXPECT_EQ(f["bytes"].get<std::size_t>(), bytes.size()) << f["path"];
    EXPECT_EQ(f["sha256"], sha256_hex(bytes)) << f["path"];
    ++listed;
  }
  int on_disk = 0;
  const std::string hash = centre.store->user_by_name("alice")->password_hash;
  ASSERT_FALSE(hash.empty());
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(dir)) {
    if (!e.is_regular_file()) continue;
    const std::string bytes = read_all(e.path().string());
    EXPECT_EQ(bytes.find(hash), std::string::npos) << e.path();
    EXPECT_EQ(bytes.find("$argon2"), std::string::npos) << e.path();
    EXPECT_EQ(bytes.find("password"), std::string::npos) << e.path();
    ++on_disk;
  }
  EXPECT_EQ(listed, 5);
  EXPECT_EQ(on_disk, listed + 1);
}

TEST_P(ExportTest, AnUnknownUserOrAFolderNotEmptyIsOneLineAndWritesNothing) {
  ApiFixture centre(GetParam());
  centre.user("alice", Role::kTrainee);
  const fs::path folder = temp_folder();

  const Result<UserExport> unknown = export_user(*centre.store, "mallory", (folder / "out").string(), "dpo", 1);
  ASSERT_FALSE(unknown);
  EXPECT_EQ(unknown.error().status, 404);
  EXPECT_EQ(unknown.error().message, "no user 'mallory'");
  EXPECT_FALSE(fs::exists(folder / "out"));

  const fs::path full = folder / "full";
  fs::create_directories(full);
  std::ofstream(full / "notes.txt") << "kept\n";
  const Result<UserExport> refused = export_user(*centre.store, "alice", full.string(), "dpo", 1);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().status, 400);
  EXPECT_EQ(refused.error().message, full.string() + ": not empty; an export goes into a new or empty folder");
  EXPECT_EQ(read_all((full / "notes.txt").string()), "kept\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(full), fs::directory_iterator()), 1);
  EXPECT_EQ(export_rows(centre), 0);

  // An empty folder that exists is fine: an export with no results is the account and the audit row.
  fs::create_directories(folder / "empty");
  const Result<UserExport> empty = export_user(*centre.store, "alice", (folder / "empty").string(), "dpo", 1);
  ASSERT_TRUE(empty) << empty.error().message;
  EXPECT_EQ(empty.value().results, 0);
  EXPECT_EQ(read_json(folder / "empty" / "results.json"), json::array());
  EXPECT_EQ(export_rows(centre), 1);
}

TEST_P(ExportTest, TheProgramsExitCodesAndLinesAreTheDocumentedOnes) {
  ApiFixture centre(GetParam());
  centre.user("alice", Role::kTrainee);
  const fs::path folder = temp_folder();
  const std::string log = (folder / "program.log").string();
  const auto run = [&](const std::string& name, const fs::path& dir) {
    fs::remove(log);
    testing::ChildOptions options;
    options.stdout_file = log;
    return testing::run_process({testing::sibling_program("cathbox-server"), "--db", centre.db_url, "admin", "export-user", name, dir.string()},
                                options);
  };
  EXPECT_EQ(run("alice", folder / "out"), 0);
  EXPECT_EQ(read_all(log).rfind("exported alice to " + (folder / "out").string() + ": 0 results, 4 files, ", 0), 0U) << read_all(log);
  EXPECT_EQ(run("alice", folder / "out"), 2);
  EXPECT_EQ(read_all(log), "cathbox-server: " + (folder / "out").string() + ": not empty; an export goes into a new or empty folder\n");
  EXPECT_EQ(run("mallory", folder / "other"), 1);
  EXPECT_EQ(read_all(log), "cathbox-server: no user 'mallory'\n");
  EXPECT_FALSE(fs::exists(folder / "other"));
  EXPECT_EQ(export_rows(centre), 1);
}

INSTANTIATE_TEST_SUITE_P(Backends, ExportTest, ::testing::ValuesIn(kBackends), BackendName());

}  // namespace
}  // namespace cathbox::server::test
