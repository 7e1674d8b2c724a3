// cathbox-trainer joins a real cathbox-server (the program, on SQLite and on PostgreSQL): the
// trainee logs in, gets the assigned case, runs it (headless, scripted hand, virtual time) while
// an instructor watches the live stream, and the record is uploaded, checked and counted for
// the assignment. With the server down the trainer works offline from its cache and queues the
// records; when the server is back they upload once each (none lost, none duplicated).
#include <gtest/gtest.h>

#include <stdlib.h>

#include <filesystem>
#include <fstream>
#include <set>

#include <nlohmann/json.hpp>

#include "server/auth.hpp"
#include "server/client.hpp"
#include "server/migrations.hpp"
#include "server/testing/server_process.hpp"
#include "server/testing/test_ca.hpp"
#include "server/tls.hpp"
#include "support/server_fixture.hpp"

namespace cathbox::server {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

constexpr const char* kRig = "rig-07";

void make_accounts(const std::string& db_url) {
  DatabaseOpen opened = open_database(db_url);
  if (!opened.db) throw std::runtime_error(opened.error);
  ASSERT_TRUE(migrate(*opened.db));
  Store store(std::move(opened.db));
  SystemClock clock;
  Auth auth(store, clock, PasswordHasher(test_argon2_params()));
  ASSERT_TRUE(auth.create_user("teacher", Role::kInstructor, "password-123"));
  ASSERT_TRUE(auth.create_user("ann", Role::kTrainee, "ann-password-9"));
}

// The trainee's rig: its own data, cache and config folders, and the password in a file.
struct Rig {
  std::string home = test::temp_folder();
  std::string password_file = home + "/password";
  Rig() {
    std::ofstream(password_file) << "ann-password-9\n";
    ::setenv("XDG_DATA_HOME", (home + "/data").c_str(), 1);
    ::setenv("XDG_CACHE_HOME", (home + "/cache").c_str(), 1);
    ::setenv("XDG_CONFIG_HOME", (home + "/config").c_str(), 1);
  }
  [[nodiscard]] std::string queue() const { return home + "/data/cathbox/upload-queue/pending"; }
  [[nodiscard]] std::vector<std::string> pending_meta() const {
    std::vector<std::string> out;
    std::error_code ec;
    for (const auto& e : fs::directory_iterator(queue(), ec)) {
      if (e.path().extension() == ".json") {
        std::ifstream in(e.path());
        out.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
      }
    }
    return out;
  }
};

struct TrainerRun {
  int exit_code = -1;
  std::string output;
};

// The trainer's stdout and stderr, one string; started through `extra` arguments.
TrainerRun run_trainer(const std::string& base_url, const Rig& rig, const std::vector<std::string>& extra = {}) {
  std::vector<std::string> argv = {testing::sibling_program("cathbox-trainer"), "--headless", "--no-box", "--server", base_url,
                                   "--user", "ann", "--password-file", rig.password_file, "--rig", kRig};
  argv.insert(argv.end(), extra.begin(), extra.end());
  testing::ChildOptions o;
  o.stdout_file = rig.home + "/trainer.log";
  std::error_code ec;
  fs::remove(o.stdout_file, ec);
  TrainerRun r;
  r.exit_code = testing::run_process(argv, o);
  std::ifstream in(o.stdout_file);
  r.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return r;
}

json get_json(ServerClient& c, const std::string& target) {
  const HttpAnswer a = c.http().get(target);
  EXPECT_EQ(a.status, 200) << target << ": " << a.body;
  return json::parse(a.body);
}

// The bundled Y bifurcation as library case "ybif".
void add_ybif_case(ServerClient& teacher) {
  const json case_body = {{"name", "ybif"},
                          {"case_file", "y_bifurcation.case"},
                          {"case", test::source_file("cases/y_bifurcation.case")},
                          {"hclm_file", "y_bifurcation.hclm"},
                          {"hclm", test::source_file("cases/y_bifurcation.hclm")}};
  ASSERT_EQ(teacher.http().post_json("/api/v1/cases", case_body.dump()).status, 201);
}

class TrainerJoin : public ::testing::TestWithParam<std::string> {};

TEST_P(TrainerJoin, AssignedRunIsWatchedLiveUploadedAndQueuedWhileOffline) {
  const std::string url = test::fresh_database_url(GetParam());
  make_accounts(url);
  testing::ServerProcess server(url);
  ServerClient teacher(server.base_url());
  ASSERT_TRUE(teacher.login("teacher", "password-123"));
  add_ybif_case(teacher);
  const json criteria = json::array({{{"metric", "peak_wall_force_mN"}, {"op", "<="}, {"value", 200}}});
  const HttpAnswer assigned = teacher.http().post_json(
      "/api/v1/assignments", json{{"trainee", "ann"}, {"case", "ybif"}, {"criteria", criteria}, {"note", "left branch"}}.dump());
  ASSERT_EQ(assigned.status, 201) << assigned.body;
  const std::int64_t assignment = json::parse(assigned.body)["id"].get<std::int64_t>();

  // The instructor watches every rig.
  WsClient watcher(20000);
  ASSERT_TRUE(watcher.connect(server.base_url(), "/api/v1/live/watch?rigs=rig-07", teacher.token()));
  const Result<std::string> rigs = watcher.read(20000);
  ASSERT_TRUE(rigs) << rigs.error().message;
  ASSERT_EQ(json::parse(*rigs)["type"], "rigs");

  Rig rig;
  const TrainerRun online = run_trainer(server.base_url(), rig);
  ASSERT_EQ(online.exit_code, 0) << online.output;
  EXPECT_NE(online.output.find("online as ann, rig rig-07, 1 assignment"), std::string::npos) << online.output;
  EXPECT_NE(online.output.find("assignment " + std::to_string(assignment) + ": ybif"), std::string::npos) << online.output;
  EXPECT_NE(online.output.find("streaming live (assignment " + std::to_string(assignment) + ")"), std::string::npos) << online.output;
  EXPECT_NE(online.output.find("upload: 1 stored, 0 already on the server, 0 refused, 0 queued"), std::string::npos) << online.output;

  // What the watcher saw: the rig start with its trainee, case and assignment, frames of the
  // wire moving, and the end.
  bool started = false;
  bool ended = false;
  int frames = 0;
  std::set<double> tips;
  while (!ended) {
    const Result<std::string> text = watcher.read(20000);
    ASSERT_TRUE(text) << "watcher: " << text.error().message << " after " << frames << " frames";
    const json m = json::parse(*text);
    if (m["type"] == "started") {
      started = true;
      EXPECT_EQ(m["rig"]["rig"], kRig);
      EXPECT_EQ(m["rig"]["user"], "ann");
      EXPECT_EQ(m["rig"]["case"], "ybif");
      EXPECT_EQ(m["rig"]["assignment"], assignment);
    } else if (m["type"] == "frame") {
      ++frames;
      EXPECT_EQ(m["rig"], kRig);
      const json& f = m["frame"];
      ASSERT_FALSE(f["tools"].empty());
      EXPECT_GE(f["tools"][0]["nodes_mm"].size(), 2U);
      EXPECT_TRUE(f["metrics"].contains("tip_path_mm"));
      tips.insert(f["tip_mm"][0].get<double>() + 1000.0 * f["tip_mm"][1].get<double>());
    } else if (m["type"] == "ended") {
      EXPECT_EQ(m["rig"], kRig);
      ended = true;
    }
  }
  EXPECT_TRUE(started);
  EXPECT_GE(frames, 1);
  std::printf("watcher (%s): %d frames, %zu distinct tip positions\n", GetParam().c_str(), frames, tips.size());

  // The record was replayed by the server and counted for the assignment.
  json results = get_json(teacher, "/api/v1/results?assignment=" + std::to_string(assignment));
  ASSERT_EQ(results["results"].size(), 1U) << results.dump();
  EXPECT_TRUE(rig.pending_meta().empty());

  // The server goes away: the trainer runs the cached assignment and queues the record with it.
  server.kill(SIGTERM);
  for (int i = 0; i < 2; ++i) {
    const TrainerRun offline = run_trainer(server.base_url(), rig);
    ASSERT_EQ(offline.exit_code, 0) << offline.output;
    EXPECT_NE(offline.output.find("unreachable"), std::string::npos) << offline.output;
    EXPECT_NE(offline.output.find("offline, rig rig-07, 1 assignment"), std::string::npos) << offline.output;
    EXPECT_NE(offline.output.find("upload: 0 stored, 0 already on the server, 0 refused, " + std::to_string(i + 1) + " queued"),
              std::string::npos)
        << offline.output;
  }
  const std::vector<std::string> queued = rig.pending_meta();
  ASSERT_EQ(queued.size(), 2U);
  for (const std::string& meta : queued) EXPECT_EQ(json::parse(meta)["assignment"], assignment) << meta;

  // Back: the next run uploads the two queued records and its own, each once.
  server.restart();
  ASSERT_TRUE(teacher.login("teacher", "password-123"));
  const TrainerRun back = run_trainer(server.base_url(), rig, {"--assignment", std::to_string(assignment)});
  ASSERT_EQ(back.exit_code, 0) << back.output;
  EXPECT_NE(back.output.find("upload: 3 stored, 0 already on the server, 0 refused, 0 queued"), std::string::npos) << back.output;
  results = get_json(teacher, "/api/v1/results?assignment=" + std::to_string(assignment));
  std::set<std::int64_t> ids;
  for (const json& r : results["results"]) ids.insert(r["id"].get<std::int64_t>());
  EXPECT_EQ(ids.size(), 4U) << results.dump();
  EXPECT_TRUE(rig.pending_meta().empty());

  // A record queued again after it was uploaded (the trainer died before removing it) is
  // answered "already there" and not stored twice.
  std::string some_record;
  for (const auto& e : fs::directory_iterator(rig.home + "/data/cathbox/records")) some_record = e.path().string();
  ASSERT_FALSE(some_record.empty());
  const fs::path pending = rig.queue();
  fs::copy_file(some_record, pending / "0000.cbxrec");
  std::ofstream(pending / "0000.json") << json{{"assignment", assignment}}.dump();
  const TrainerRun again = run_trainer(server.base_url(), rig, {"--no-record"});
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NE(again.output.find("upload: 0 stored, 1 already on the server, 0 refused, 0 queued"), std::string::npos) << again.output;
  EXPECT_EQ(get_json(teacher, "/api/v1/results?assignment=" + std::to_string(assignment))["results"].size(), 4U);
}

// The trainer over TLS: the centre's CA given with --ca-file logs in, runs and uploads over
// HTTPS and wss://; a CA that did not sign the server's certificate is one line, never a
// fallback to plain HTTP (the run goes to the upload queue instead).
TEST(TrainerJoinTls, TheTrainerLogsInOverTlsWithTheCentresCaAndRefusesAnyOther) {
  const std::string url = test::fresh_database_url("sqlite");
  make_accounts(url);
  const std::string folder = test::temp_folder();
  const testing::TestCa ca(folder, "centre-ca");
  const testing::TestCa stranger(folder, "stranger-ca");
  const TlsFiles files = ca.issue("server", "IP:127.0.0.1");
  testing::ServerProcess server(url, 0, {"--tls-cert", files.cert_file, "--tls-key", files.key_file});
  ASSERT_EQ(server.base_url().rfind("https://", 0), 0U);
  set_client_ca_file(ca.ca_file());
  ServerClient teacher(server.base_url());
  ASSERT_TRUE(teacher.login("teacher", "password-123"));
  add_ybif_case(teacher);
  ASSERT_EQ(teacher.http().post_json("/api/v1/assignments", json{{"trainee", "ann"}, {"case", "ybif"}, {"criteria", json::array()}}.dump()).status,
            201);

  Rig rig;
  const TrainerRun refused = run_trainer(server.base_url(), rig, {"--ca-file", stranger.ca_file()});
  EXPECT_NE(refused.output.find("TLS to 127.0.0.1:" + std::to_string(server.port()) +
                                ": certificate verify failed: unable to get local issuer certificate (trusting --ca-file " +
                                stranger.ca_file() + ")"),
            std::string::npos)
      << refused.output;
  EXPECT_EQ(get_json(teacher, "/api/v1/results")["results"].size(), 0U);

  const TrainerRun online = run_trainer(server.base_url(), rig, {"--ca-file", ca.ca_file()});
  ASSERT_EQ(online.exit_code, 0) << online.output;
  EXPECT_NE(online.output.find("online as ann, rig rig-07, 1 assignment"), std::string::npos) << online.output;
  EXPECT_NE(online.output.find("streaming live"), std::string::npos) << online.output;
  // This run's record and the one queued while the certificate was refused.
  EXPECT_NE(online.output.find("upload: 2 stored"), std::string::npos) << online.output;
  EXPECT_EQ(get_json(teacher, "/api/v1/results")["results"].size(), 2U);
  set_client_ca_file("");
}

TEST(TrainerJoinOptions, BadSettingsAndMissingPasswordAreRefusedWithOneLine) {
  Rig rig;
  fs::create_directories(rig.home + "/config/cathbox");
  std::ofstream(rig.home + "/config/cathbox/trainer.json") << R"({"server": "http://127.0.0.1:1", "usr": "ann"})";
  testing::ChildOptions o;
  o.stdout_file = rig.home + "/bad.log";
  EXPECT_EQ(testing::run_process({testing::sibling_program("cathbox-trainer"), "--headless", "--no-box"}, o), 2);
  std::ifstream in(o.stdout_file);
  const std::string out((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(out.find("trainer.json: field 'usr': unknown field"), std::string::npos) << out;

  std::ofstream(rig.home + "/config/cathbox/trainer.json") << R"({"server": "http://127.0.0.1:1", "user": "ann"})";
  ::unsetenv("CATHBOX_PASSWORD");
  o.stdout_file = rig.home + "/nopass.log";
  EXPECT_EQ(testing::run_process({testing::sibling_program("cathbox-trainer"), "--headless", "--no-box"}, o), 2);
  std::ifstream in2(o.stdout_file);
  const std::string out2((std::istreambuf_iterator<char>(in2)), std::istreambuf_iterator<char>());
  EXPECT_NE(out2.find("--server needs a password"), std::string::npos) << out2;
}

INSTANTIATE_TEST_SUITE_P(Backends, TrainerJoin, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
