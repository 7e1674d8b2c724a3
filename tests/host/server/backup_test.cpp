// Backup and restore of a centre's database on SQLite (the online backup API) and PostgreSQL
// (pg_dump custom format): a centre with users, a case, an assignment and a result from a real
// record is backed up, restored into an empty database, and the restored centre answers the same
// users, cases, assignments, results and record bytes, and serves the debrief (a new replay of
// the record, every state hash checked). Bad input: a foreign file, a backup of the other kind,
// a target that is not empty; none of them touches the target.
#include <filesystem>
#include <fstream>
#include <iterator>

#include "server/backup.hpp"
#include "record_files.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server::test {
namespace {

using nlohmann::json;

// What a centre holds, as its API shows it to an admin: users, cases, assignments, results.
json centre_view(ApiFixture& f, const std::string& token) {
  json view;
  for (const char* list : {"/api/v1/users", "/api/v1/cases", "/api/v1/assignments", "/api/v1/results"}) {
    const ApiResponse r = f.call("GET", list, "", token);
    EXPECT_EQ(r.status, 200) << list << ": " << r.body;
    view[list] = json::parse(r.body);
  }
  return view;
}

class BackupTest : public ::testing::TestWithParam<std::string> {};

TEST_P(BackupTest, ARestoreIntoAnEmptyDatabaseIsTheSameCentreAndServesTheDebrief) {
  const std::string folder = temp_folder();
  ApiFixture centre(GetParam(), make_session_checker());
  const std::string root = centre.user("root", Role::kAdmin);
  const std::string teacher = centre.user("teacher", Role::kInstructor);
  const std::string alice = centre.user("alice", Role::kTrainee);
  ASSERT_EQ(centre.upload_bundled_case("y_bifurcation", "ybif", teacher).status, 201);
  const json a = centre.call_json("POST", "/api/v1/assignments",
                                  {{"trainee", "alice"}, {"case", "ybif"},
                                   {"criteria", json::array({{{"metric", "tip_path_mm"}, {"op", ">="}, {"value", 50}}})}},
                                  teacher, 201);
  const std::string record = read_all(record_left_branch({}, "backup_left.cbxrec"));
  const ApiResponse stored = centre.call("POST", "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>()), record, alice);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const int result_id = json::parse(stored.body)["id"].get<int>();
  const json before = centre_view(centre, root);

  const std::string file = folder + "/centre.backup";
  const Status backed_up = backup_database(centre.db_url, file);  // while the centre is open
  ASSERT_TRUE(backed_up) << backed_up.error().message;
  EXPECT_FALSE(std::filesystem::exists(file + ".partial"));

  const std::string target = fresh_database_url(GetParam());
  const Status restored = restore_database(target, file);
  ASSERT_TRUE(restored) << restored.error().message;
  ApiFixture again(GetParam(), make_session_checker(), target);
  const std::string root_again = again.login("root");  // the same password hash
  EXPECT_EQ(centre_view(again, root_again), before);
  const std::string result = "/api/v1/results/" + std::to_string(result_id);
  const ApiResponse bytes = again.call("GET", result + "/record", "", root_again);
  ASSERT_EQ(bytes.status, 200);
  EXPECT_EQ(bytes.body, record);
  const ApiResponse debrief = again.call("GET", result + "/trace", "", root_again);  // a new replay: no cache here
  ASSERT_EQ(debrief.status, 200) << debrief.body;
  EXPECT_EQ(json::parse(debrief.body)["result"]["id"], result_id);
  // The restored centre goes on: the same record is the same result, a new user is a new id.
  EXPECT_EQ(again.call("POST", "/api/v1/results", record, again.login("alice")).status, 200);
  again.user("carol", Role::kTrainee);
}

TEST_P(BackupTest, BadInputIsOneLineAndLeavesTheTargetAsItWas) {
  const std::string folder = temp_folder();
  ApiFixture centre(GetParam());
  centre.user("root", Role::kAdmin);
  const std::string file = folder + "/centre.backup";
  ASSERT_TRUE(backup_database(centre.db_url, file));

  // Into a database that holds a centre already.
  const Status full = restore_database(centre.db_url, file);
  ASSERT_FALSE(full);
  EXPECT_EQ(full.error().status, 400);
  if (GetParam() == "sqlite") {
    EXPECT_EQ(full.error().message, "--db " + centre.db_url + ": the file exists; a restore goes into a new database file");
  } else {
    EXPECT_EQ(full.error().message.rfind("--db: the database is not empty (", 0), 0U) << full.error().message;
  }
  EXPECT_EQ(centre.call("POST", "/api/v1/login", R"({"name":"root","password":"password-123"})").status, 200);

  const std::string target = fresh_database_url(GetParam());
  const std::string foreign = folder + "/notes.txt";
  std::ofstream(foreign) << "not a backup\n";
  const Status not_backup = restore_database(target, foreign);
  ASSERT_FALSE(not_backup);
  EXPECT_EQ(not_backup.error().message,
            foreign + ": not a cathbox backup (neither a SQLite database nor a pg_dump custom-format file)");
  const Status missing = restore_database(target, folder + "/absent.backup");
  ASSERT_FALSE(missing);
  EXPECT_EQ(missing.error().message, folder + "/absent.backup: no such backup file");

  // A backup of the other kind of database.
  const std::string other = GetParam() == "sqlite" ? "postgresql" : "sqlite";
  const Status crossed = restore_database(fresh_database_url(other), file);
  ASSERT_FALSE(crossed);
  EXPECT_EQ(crossed.error().message,
            file + (GetParam() == "sqlite" ? ": a SQLite backup: restore it with a sqlite:PATH --db"
                                           : ": a PostgreSQL backup: restore it with a postgresql://... --db"));
  // The target is still empty: a restore into it works.
  ASSERT_TRUE(restore_database(target, file));

  // A backup into a folder that does not exist.
  const Status unwritable = backup_database(centre.db_url, folder + "/no/such/dir/b.backup");
  ASSERT_FALSE(unwritable);
  EXPECT_EQ(unwritable.error().status, 400);
  EXPECT_EQ(unwritable.error().message.rfind(folder + "/no/such/dir/b.backup: cannot write: ", 0), 0U) << unwritable.error().message;
}

INSTANTIATE_TEST_SUITE_P(Backends, BackupTest, ::testing::ValuesIn(kBackends), BackendName());

}  // namespace
}  // namespace cathbox::server::test
