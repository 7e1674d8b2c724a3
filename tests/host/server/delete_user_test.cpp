// DELETE /api/v1/users/{name} on SQLite and PostgreSQL: the account and every result, record,
// metric, assignment, token and login failure of theirs go in one transaction, the traces
// derived from their records leave the cache (memory and disk), their live streams end;
// afterwards no endpoint answers anything of theirs (an instructor sees 404s, lists without
// them), the export knows no such user, and no file under the data folder holds their record;
// admins only, not oneself; audited with who, when and from where. An unknown name changes
// nothing. `cathbox-server admin delete-user` (a stopped server) does the same from the command line.
#include <filesystem>

#include <gtest/gtest.h>

#include "server/artifact_cache.hpp"
#include "server/audit_log.hpp"
#include "server/testing/child_process.hpp"
#include "server/user_export.hpp"
#include "support/api_fixture.hpp"
#include "support/server_fixture.hpp"

namespace cathbox::server {
namespace {

namespace fs = std::filesystem;
using test::error_of;
using test::FakeRecords;
using json = nlohmann::json;

std::string read_bytes(const fs::path& path) { return test::file_bytes(path.string()); }

// Every regular file under `folder` whose name or bytes contain `needle`.
std::vector<std::string> files_holding(const fs::path& folder, const std::string& needle) {
  std::vector<std::string> found;
  for (const fs::directory_entry& e : fs::recursive_directory_iterator(folder)) {
    if (!e.is_regular_file()) continue;
    if (e.path().filename().string().find(needle) != std::string::npos || read_bytes(e.path()).find(needle) != std::string::npos) {
      found.push_back(e.path().string());
    }
  }
  return found;
}

// A subscriber that keeps what it is given (the hub calls deliver() under its lock).
class Inbox final : public LiveSubscriber {
 public:
  void deliver(const LiveMessage& message) override { got.push_back(*message); }
  std::vector<std::string> got;
};

using DeleteUserTest = test::CentreTest;

std::string header(const ApiResponse& r, const std::string& name) {
  for (const auto& [n, v] : r.headers) {
    if (n == name) return v;
  }
  return "";
}

TEST_P(DeleteUserTest, NothingOfTheTraineeIsLeftInAnyEndpointOrTheCache) {
  ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  const json a = f_->call_json("POST", "/api/v1/assignments", {{"trainee", "alice"}, {"case", "ybif"}}, teacher_, 201);
  const std::string record = FakeRecords::make("y_bifurcation", {{"target_reached", 1}});
  const ApiResponse stored = f_->call("POST", "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>()), record, alice_);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const std::string id = std::to_string(json::parse(stored.body)["id"].get<int>());
  ASSERT_EQ(f_->call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {}, false, "bob"), bob_).status, 201);
  const ApiResponse first = f_->call("GET", "/api/v1/results/" + id + "/trace", "", teacher_);
  ASSERT_EQ(first.status, 200);
  ASSERT_EQ(header(f_->call("GET", "/api/v1/results/" + id + "/trace", "", teacher_), "X-Cathbox-Trace").rfind("cached", 0), 0U);
  EXPECT_EQ(f_->call("POST", "/api/v1/login", R"({"name":"alice","password":"wrong-one"})").status, 401);  // a login failure

  EXPECT_EQ(f_->call("DELETE", "/api/v1/users/alice", "", admin_).status, 204);

  // What an instructor sees afterwards: her result, record and trace are gone, as if never there.
  for (const std::string& path : {"/api/v1/results/" + id, "/api/v1/results/" + id + "/record", "/api/v1/results/" + id + "/trace"}) {
    EXPECT_EQ(f_->call("GET", path, "", teacher_).status, 404) << path;
  }
  EXPECT_EQ(f_->call("GET", "/api/v1/results?trainee=alice", "", teacher_).status, 404);
  const json results = f_->call_json("GET", "/api/v1/results", nullptr, teacher_, 200);
  ASSERT_EQ(results["results"].size(), 1U) << "bob's stays";
  EXPECT_EQ(results["results"][0]["trainee"], "bob");
  EXPECT_EQ(f_->call_json("GET", "/api/v1/assignments", nullptr, teacher_, 200)["assignments"].size(), 0U);
  EXPECT_EQ(f_->call("GET", "/api/v1/assignments/" + std::to_string(a["id"].get<int>()), "", teacher_).status, 404);
  for (const json& u : f_->call_json("GET", "/api/v1/users", nullptr, admin_, 200)["users"]) EXPECT_NE(u["name"], "alice");
  EXPECT_EQ(f_->call("GET", "/api/v1/me", "", alice_).status, 401);
  EXPECT_EQ(f_->store->login_failures_since("alice", 0), 0);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/cases", nullptr, teacher_, 200)["cases"].size(), 1U) << "the library stays";

  // A new account of the same name starts empty; the same record is a new result whose trace
  // is replayed again: the cache held nothing of hers.
  const std::string again = f_->user("alice", Role::kTrainee);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results?trainee=alice", nullptr, teacher_, 200)["results"].size(), 0U);
  const ApiResponse restored = f_->call("POST", "/api/v1/results", record, again);
  ASSERT_EQ(restored.status, 201) << restored.body;
  const std::string new_id = std::to_string(json::parse(restored.body)["id"].get<int>());
  EXPECT_EQ(header(f_->call("GET", "/api/v1/results/" + new_id + "/trace", "", teacher_), "X-Cathbox-Trace").rfind("replayed", 0), 0U);

  const json log = f_->call_json("GET", "/api/v1/audit?limit=1", nullptr, admin_, 200);
  ASSERT_EQ(log["entries"].size(), 1U);
  EXPECT_EQ(log["entries"][0]["action"], "user.delete");
  EXPECT_EQ(log["entries"][0]["target"], "alice");
  EXPECT_EQ(log["entries"][0]["detail"], "results=1");
}

TEST_P(DeleteUserTest, OnlyAdminsAndNotThemselves) {
  EXPECT_EQ(f_->call("DELETE", "/api/v1/users/bob", "", teacher_).status, 403);
  EXPECT_EQ(f_->call("DELETE", "/api/v1/users/bob", "", alice_).status, 403);
  const ApiResponse missing = f_->call("DELETE", "/api/v1/users/nobody", "", admin_);
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(error_of(missing), "no user 'nobody'");
  const ApiResponse self = f_->call("DELETE", "/api/v1/users/root", "", admin_);
  EXPECT_EQ(self.status, 409);
  EXPECT_EQ(error_of(self), "'root' is you: another admin deletes your account");
  const std::string other = f_->user("root2", Role::kAdmin);
  EXPECT_EQ(f_->call("DELETE", "/api/v1/users/root", "", other).status, 204) << "another admin may";
  EXPECT_EQ(f_->call("GET", "/api/v1/me", "", admin_).status, 401);
}

// The delete's audit row: who (the admin), when (the server's clock), from where (the request's
// address), what (the account, how many results).
TEST_P(DeleteUserTest, TheAuditRowSaysWhoWhenAndFromWhere) {
  ASSERT_EQ(f_->call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {}, false, "a1"), alice_).status, 201);
  f_->clock.advance_us(5'000'000);
  ASSERT_EQ(f_->call("DELETE", "/api/v1/users/alice", "", admin_, "192.0.2.7").status, 204);
  const std::vector<AuditEntry> log = audit_entries(f_->store->database(), {});
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log[0].action, "user.delete");
  EXPECT_EQ(log[0].actor, "root");
  EXPECT_EQ(log[0].at_us, f_->clock.now_us());
  EXPECT_EQ(log[0].remote, "192.0.2.7");
  EXPECT_EQ(log[0].target, "alice");
  EXPECT_EQ(log[0].detail, "results=1");
  // The export (a subject-access request) knows no such account any more.
  const Result<UserExport> exported = export_user(*f_->store, "alice", (fs::path(test::temp_folder()) / "out").string(), "dpo", 1);
  ASSERT_FALSE(exported);
  EXPECT_EQ(exported.error().message, "no user 'alice'");
}

// An unknown name: one line, 404, and nothing changes (no row, no audit entry, no cache entry).
TEST_P(DeleteUserTest, AnUnknownUserIsOneLineAndChangesNothing) {
  ASSERT_EQ(f_->call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {}, false, "a1"), alice_).status, 201);
  const std::size_t users = f_->store->list_users().size();
  const std::size_t rows = audit_entries(f_->store->database(), {}).size();
  const ApiResponse missing = f_->call("DELETE", "/api/v1/users/mallory", "", admin_);
  EXPECT_EQ(missing.status, 404);
  EXPECT_EQ(missing.body, R"({"error":"no user 'mallory'"})");
  EXPECT_EQ(f_->store->list_users().size(), users);
  EXPECT_EQ(audit_entries(f_->store->database(), {}).size(), rows);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results", nullptr, teacher_, 200)["results"].size(), 1U);
}

// A trainee streaming live when deleted: the stream ends at once (watchers told "ended", the
// rig list without it), and a frame still arriving on the open socket is not passed on but ends
// the stream. Another trainee's stream goes on.
TEST_P(DeleteUserTest, TheirLiveStreamsEndAndCarryNothingMore) {
  LiveService& live = f_->core->live();
  const auto caller = [&](const std::string& name) {
    const std::optional<User> u = f_->store->user_by_name(name);
    return Caller{u->id, u->name, u->role, ""};
  };
  Result<Publisher> hers = live.start(caller("alice"), "rig-a", "ybif", 0, std::nullopt);
  Result<Publisher> his = live.start(caller("bob"), "rig-b", "ybif", 0, std::nullopt);
  ASSERT_TRUE(hers && his);
  auto watcher = std::make_shared<Inbox>();
  f_->core->hub().subscribe("rig-a", watcher);
  f_->core->hub().subscribe("rig-b", watcher);
  f_->core->hub().subscribe_events(watcher);
  const std::string frame = R"({"type":"frame","seq":1,"t_ms":0})";
  ASSERT_TRUE(live.message(hers.value(), frame));
  ASSERT_EQ(watcher->got.size(), 1U);

  ASSERT_EQ(f_->call("DELETE", "/api/v1/users/alice", "", admin_).status, 204);
  ASSERT_EQ(watcher->got.size(), 2U);
  EXPECT_EQ(json::parse(watcher->got[1]), json::parse(R"({"type":"ended","rig":"rig-a"})"));
  const json rigs = f_->call_json("GET", "/api/v1/live/rigs", nullptr, teacher_, 200);
  ASSERT_EQ(rigs["rigs"].size(), 1U) << rigs.dump();
  EXPECT_EQ(rigs["rigs"][0]["rig"], "rig-b");

  ASSERT_TRUE(live.message(hers.value(), frame));
  EXPECT_TRUE(hers.value().ended);
  EXPECT_EQ(watcher->got.size(), 2U) << "her frame went on: " << watcher->got.back();
  live.finish(hers.value());  // the socket closing changes nothing more
  EXPECT_EQ(watcher->got.size(), 2U);
  ASSERT_TRUE(live.message(his.value(), frame));
  EXPECT_FALSE(his.value().ended);
  EXPECT_EQ(watcher->got.size(), 3U);
  // Her rig name is free again.
  EXPECT_TRUE(live.start(caller("bob"), "rig-a", "ybif", 0, std::nullopt));
}

// The same over real sockets: her rig streaming, an instructor watching it. After the delete the
// watcher is told her stream ended, her next message makes the server close her socket, and the
// rig list is empty.
TEST_P(DeleteUserTest, OverRealSocketsHerStreamEndsForItsWatchers) {
  ManualClock clock;
  test::ServerOptions options;
  options.clock = &clock;  // no sweep runs: the socket closes because of the delete, not a token recheck
  test::RunningServer server(GetParam(), options);
  const std::string root = server.token_for("root", Role::kAdmin);
  const std::string teacher = server.token_for("teacher", Role::kInstructor);
  const std::string alice = server.token_for("alice", Role::kTrainee);
  WsClient watcher, stream;
  std::string error;
  ASSERT_TRUE(watcher.connect(server.base_url(), "/api/v1/live/watch?rigs=rig-a", teacher));
  ASSERT_TRUE(stream.connect(server.base_url(), "/api/v1/live/rigs/rig-a/stream?case=ybif", alice));
  const std::string frame = R"({"type":"frame","seq":1,"t_ms":0})";
  ASSERT_TRUE(stream.send(frame));
  // The watcher's messages up to the first that contains `what`.
  const auto read_until = [&](const std::string& what) {
    for (int i = 0; i < 8; ++i) {
      const Result<std::string> m = watcher.read(10000);
      if (!m) {
        error = m.error().message;
        return false;
      }
      if (m->find(what) != std::string::npos) return true;
    }
    return false;
  };
  ASSERT_TRUE(read_until(R"("type":"frame")")) << error;

  HttpClient http(server.base_url());
  http.set_token(root);
  ASSERT_EQ(http.request("DELETE", "/api/v1/users/alice").status, 204);
  EXPECT_TRUE(read_until(R"("type":"ended")")) << error;
  ASSERT_TRUE(stream.send(frame));
  bool closed = false;
  for (int i = 0; i < 3 && !closed; ++i) {
    const Result<std::string> m = stream.read(10000);
    error = m ? std::string() : m.error().message;
    closed = !m && error != WsClient::kReadTimeout;
  }
  EXPECT_TRUE(closed) << error;
  http.set_token(teacher);
  EXPECT_EQ(http.get("/api/v1/live/rigs").body, R"({"rigs":[]})");
}

INSTANTIATE_TEST_SUITE_P(Backends, DeleteUserTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

// The data folder as a server keeps it (SQLite's file inside it, the trace cache in DATA/cache):
// after the delete no file there holds her record's bytes, its hash (the trace file's name) or
// her result, while bob's are still found by the same search (the search can see them).
class DeleteUserFilesTest : public ::testing::TestWithParam<std::string> {};

TEST_P(DeleteUserFilesTest, NoFileUnderTheDataFolderHoldsTheirRecord) {
  const fs::path data = test::temp_folder();
  const bool sqlite = GetParam() == "sqlite";
  test::ApiFixture f(GetParam(), std::make_unique<FakeRecords>(), sqlite ? "sqlite:" + (data / "server.db").string() : "",
                     [&](ServerConfig& c) { c.cache_dir = (data / "cache").string(); });
  const std::string admin = f.user("root", Role::kAdmin);
  const std::string teacher = f.user("teacher", Role::kInstructor);
  const std::string alice = f.user("alice", Role::kTrainee);
  const std::string bob = f.user("bob", Role::kTrainee);
  const std::string hers = FakeRecords::make("y_bifurcation", {{"tip_path_mm", 81.25}}, false, "alice-private-7e1f");
  const std::string his = FakeRecords::make("y_bifurcation", {{"tip_path_mm", 64.5}}, false, "bob-private-91c2");
  // One record of hers reaches the database file itself (a checkpoint: only secure_delete
  // removes it there), the other stays in SQLite's write-ahead log (only the scrub's truncation
  // removes it there).
  ASSERT_EQ(f.call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {}, false, "alice-earlier-5d0b"), alice).status, 201);
  f.store->database().scrub();
  const json a = json::parse(f.call("POST", "/api/v1/results", hers, alice).body);
  const json b = json::parse(f.call("POST", "/api/v1/results", his, bob).body);
  for (const json* r : {&a, &b}) {
    ASSERT_EQ(f.call("GET", "/api/v1/results/" + std::to_string((*r)["id"].get<int>()) + "/trace", "", teacher).status, 200);
  }
  const std::string her_hash = a["content_hash"], his_hash = b["content_hash"];
  const auto trace_file = [&](const std::string& hash) { return data / "cache" / cache_file_name(trace_cache_key(hash)); };
  ASSERT_TRUE(fs::exists(trace_file(her_hash))) << "her trace file is on disk before";
  if (sqlite) {
    ASSERT_NE(read_bytes(data / "server.db").find("alice-earlier-5d0b"), std::string::npos);
    ASSERT_EQ(files_holding(data, "alice-private-7e1f"), std::vector<std::string>{(data / "server.db-wal").string()});
  }

  ASSERT_EQ(f.call("DELETE", "/api/v1/users/alice", "", admin).status, 204);
  EXPECT_EQ(files_holding(data, "alice-private-7e1f"), std::vector<std::string>{});
  EXPECT_EQ(files_holding(data, "alice-earlier-5d0b"), std::vector<std::string>{});
  EXPECT_EQ(files_holding(data, her_hash), std::vector<std::string>{});
  EXPECT_EQ(files_holding(data, "81.25"), std::vector<std::string>{});  // her metric
  EXPECT_TRUE(fs::exists(trace_file(his_hash))) << "bob's trace file stays";
  if (sqlite) {
    EXPECT_FALSE(files_holding(data, "bob-private-91c2").empty());
  }
  // The trace of his record still comes from the cache; hers is no longer anywhere.
  const ApiResponse trace = f.call("GET", "/api/v1/results/" + std::to_string(b["id"].get<int>()) + "/trace", "", teacher);
  EXPECT_EQ(trace.status, 200);
}

// `cathbox-server admin delete-user NAME` on a stopped server's database and data folder: the
// same delete and audit row (actor $USER, from "cli"), the trace files of her records removed;
// an unknown user or the last admin is one line and exit 1, nothing changed.
TEST_P(DeleteUserFilesTest, TheCommandLineDeletesAndAnswersTheDocumentedExitCodes) {
  const fs::path data = test::temp_folder();
  const bool sqlite = GetParam() == "sqlite";
  std::string url;
  std::string her_hash, his_hash;
  {
    test::ApiFixture f(GetParam(), std::make_unique<FakeRecords>(), sqlite ? "sqlite:" + (data / "server.db").string() : "",
                       [&](ServerConfig& c) { c.cache_dir = (data / "cache").string(); });
    url = f.db_url;
    (void)f.user("root", Role::kAdmin);
    const std::string teacher = f.user("teacher", Role::kInstructor);
    const std::string alice = f.user("alice", Role::kTrainee);
    const std::string bob = f.user("bob", Role::kTrainee);
    const json a = json::parse(f.call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {}, false, "cli-a"), alice).body);
    const json b = json::parse(f.call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {}, false, "cli-b"), bob).body);
    for (const json* r : {&a, &b}) {
      ASSERT_EQ(f.call("GET", "/api/v1/results/" + std::to_string((*r)["id"].get<int>()) + "/trace", "", teacher).status, 200);
    }
    her_hash = a["content_hash"];
    his_hash = b["content_hash"];
  }  // the server stops
  const std::string log = (fs::path(test::temp_folder()) / "program.log").string();
  const auto run = [&](const std::string& name) {
    fs::remove(log);
    testing::ChildOptions options;
    options.stdout_file = log;
    return testing::run_process(
        {testing::sibling_program("cathbox-server"), "--db", url, "--data", data.string(), "admin", "delete-user", name}, options);
  };
  ASSERT_EQ(files_holding(data / "cache", her_hash).size(), 1U);
  EXPECT_EQ(run("alice"), 0);
  EXPECT_EQ(read_bytes(log), "deleted alice: 1 results with their records\n");
  EXPECT_EQ(files_holding(data / "cache", her_hash), std::vector<std::string>{});
  EXPECT_EQ(files_holding(data / "cache", his_hash).size(), 1U);
  if (sqlite) {
    EXPECT_EQ(files_holding(data, "cli-a"), std::vector<std::string>{});
  }
  EXPECT_EQ(run("alice"), 1);
  EXPECT_EQ(read_bytes(log), "cathbox-server: no user 'alice'\n");
  EXPECT_EQ(run("root"), 1);
  EXPECT_EQ(read_bytes(log), "cathbox-server: 'root' is the last admin\n");

  test::ApiFixture again(GetParam(), std::make_unique<FakeRecords>(), url);
  EXPECT_FALSE(again.store->user_by_name("alice"));
  EXPECT_TRUE(again.store->user_by_name("root"));
  EXPECT_EQ(again.store->list_results({}).size(), 1U);
  const std::vector<AuditEntry> rows = audit_entries(again.store->database(), {});
  ASSERT_FALSE(rows.empty());
  EXPECT_EQ(rows[0].action, "user.delete");
  EXPECT_EQ(rows[0].target, "alice");
  EXPECT_EQ(rows[0].remote, "cli");
  EXPECT_EQ(rows[0].detail, "results=1");
  EXPECT_EQ(std::count_if(rows.begin(), rows.end(), [](const AuditEntry& e) { return e.action == "user.delete"; }), 1);
}

INSTANTIATE_TEST_SUITE_P(Backends, DeleteUserFilesTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
