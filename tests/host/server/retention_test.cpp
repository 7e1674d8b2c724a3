// The record retention setting (ServerConfig::record_retention_days, `--record-retention-days`)
// in virtual time (the fixture's ManualClock; ServerCore::enforce_retention is the maintenance
// thread's step), on SQLite and PostgreSQL: records uploaded more than N days ago leave the store
// and their traces the cache (memory and disk); their results and metrics stay, marked
// `record_gone_at`, and their record and trace answer 410 with one line; younger records stay;
// each pass that removes something is one audit row; 0 keeps everything forever.
#include <filesystem>

#include <gtest/gtest.h>

#include "server/artifact_cache.hpp"
#include "server/audit_log.hpp"
#include "server/iso_time.hpp"
#include "server/user_export.hpp"
#include "support/api_fixture.hpp"
#include "support/server_fixture.hpp"

namespace cathbox::server {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using test::FakeRecords;

constexpr std::int64_t kDayUs = 86'400'000'000;

class RetentionTest : public ::testing::TestWithParam<std::string> {
 protected:
  void open(int days) {
    f_ = std::make_unique<test::ApiFixture>(GetParam(), std::make_unique<FakeRecords>(), "", [&](ServerConfig& c) {
      c.record_retention_days = days;
      c.auth.token_lifetime_us = 4000 * kDayUs;  // the logins outlast the test's years of virtual time
      c.cache_dir = (cache_ / "cache").string();
    });
    teacher_ = f_->user("teacher", Role::kInstructor);
    alice_ = f_->user("alice", Role::kTrainee);
  }
  // Alice's upload now; its id.
  std::string upload(const std::string& salt) {
    const ApiResponse r = f_->call("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {{"tip_path_mm", 70.0}}, false, salt), alice_);
    EXPECT_EQ(r.status, 201) << r.body;
    return std::to_string(json::parse(r.body)["id"].get<int>());
  }
  int retention_rows() {
    int n = 0;
    for (const AuditEntry& e : audit_entries(f_->store->database(), {})) n += e.action == "records.retention" ? 1 : 0;
    return n;
  }
  fs::path cache_ = test::temp_folder();
  std::unique_ptr<test::ApiFixture> f_;
  std::string teacher_, alice_;
};

TEST_P(RetentionTest, RecordsOlderThanTheSettingGoAndTheirResultsStayMarked) {
  open(30);
  const std::string old_id = upload("old-run");
  const std::string old_path = "/api/v1/results/" + old_id;
  ASSERT_EQ(f_->call("GET", old_path + "/trace", "", teacher_).status, 200);  // cached, on disk too
  const std::string old_hash = f_->call_json("GET", old_path, nullptr, teacher_, 200)["content_hash"];
  ASSERT_TRUE(fs::exists(cache_ / "cache" / cache_file_name(trace_cache_key(old_hash))));
  f_->clock.advance_us(20 * kDayUs);
  const std::string young_id = upload("young-run");

  // Day 30 after the first upload, to the microsecond: not older than 30 days yet.
  f_->clock.advance_us(10 * kDayUs);
  EXPECT_EQ(f_->core->enforce_retention(), 0);
  EXPECT_EQ(f_->call("GET", old_path + "/record", "", teacher_).status, 200);
  EXPECT_EQ(retention_rows(), 0) << "a pass that removes nothing logs nothing";

  f_->clock.advance_us(1);
  EXPECT_EQ(f_->core->enforce_retention(), 1);
  const std::string gone_at = iso_time(f_->clock.now_us());
  const json result = f_->call_json("GET", old_path, nullptr, teacher_, 200);
  EXPECT_EQ(result["record_gone_at"], gone_at);
  EXPECT_FALSE(result.contains("record_url"));
  EXPECT_EQ(result["metrics"]["tip_path_mm"], 70.0) << "the result and its metrics stay";
  for (const std::string& path : {old_path + "/record", old_path + "/trace"}) {
    const ApiResponse r = f_->call("GET", path, "", teacher_);
    EXPECT_EQ(r.status, 410) << path;
    EXPECT_EQ(test::error_of(r), "result " + old_id + ": its record was removed by the retention setting at " + gone_at) << path;
  }
  EXPECT_FALSE(fs::exists(cache_ / "cache" / cache_file_name(trace_cache_key(old_hash))));
  EXPECT_FALSE(f_->store->result_record(std::stoll(old_id)));
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results?trainee=alice", nullptr, teacher_, 200)["results"].size(), 2U);
  // The younger record stays, with its trace.
  EXPECT_EQ(f_->call("GET", "/api/v1/results/" + young_id + "/record", "", teacher_).status, 200);
  EXPECT_FALSE(f_->call_json("GET", "/api/v1/results/" + young_id, nullptr, teacher_, 200).contains("record_gone_at"));

  const std::vector<AuditEntry> log = audit_entries(f_->store->database(), {});
  ASSERT_FALSE(log.empty());
  EXPECT_EQ(log[0].action, "records.retention");
  EXPECT_EQ(log[0].actor, "cathbox-server");
  EXPECT_EQ(log[0].remote, "server");
  EXPECT_EQ(log[0].at_us, f_->clock.now_us());
  EXPECT_EQ(log[0].detail, "records=1 uploaded_before=" + iso_time(f_->clock.now_us() - 30 * kDayUs) + " days=30");

  // An export lists the result without its record.
  const fs::path out = fs::path(test::temp_folder()) / "export";
  ASSERT_TRUE(export_user(*f_->store, "alice", out.string(), "dpo", f_->clock.now_us()));
  const json exported = json::parse(test::file_bytes((out / "results.json").string()));
  ASSERT_EQ(exported.size(), 2U);
  EXPECT_EQ(exported[0]["record"], nullptr);
  EXPECT_EQ(exported[0]["record_gone_us"], f_->clock.now_us());
  EXPECT_EQ(exported[1]["record"], "records/" + young_id + ".cbxrec");
  EXPECT_FALSE(fs::exists(out / "records" / (old_id + ".cbxrec")));

  // The next pass has nothing to do; twenty days on (the younger one 31 days old) it goes too.
  EXPECT_EQ(f_->core->enforce_retention(), 0);
  f_->clock.advance_us(20 * kDayUs);
  EXPECT_EQ(f_->core->enforce_retention(), 1);
  EXPECT_EQ(f_->call("GET", "/api/v1/results/" + young_id + "/record", "", teacher_).status, 410);
  EXPECT_EQ(retention_rows(), 2);
}

TEST_P(RetentionTest, ZeroKeepsRecordsForever) {
  open(0);
  const std::string id = upload("kept-run");
  f_->clock.advance_us(3650 * kDayUs);
  EXPECT_EQ(f_->core->enforce_retention(), 0);
  EXPECT_EQ(f_->call("GET", "/api/v1/results/" + id + "/record", "", teacher_).status, 200);
  EXPECT_EQ(retention_rows(), 0);
}

TEST(RetentionSetting, ANegativeNumberOfDaysIsRefusedAtOpen) {
  ServerConfig config;
  config.db_url = "sqlite::memory:";
  config.record_retention_days = -1;
  const Result<std::unique_ptr<ServerCore>> core = ServerCore::open(config);
  ASSERT_FALSE(core);
  EXPECT_EQ(core.error().status, 400);
  EXPECT_EQ(core.error().message, "--record-retention-days: expected 0 (keep) or more days");
}

// The running server applies the setting on its maintenance pass (the thread's step, run here on
// the virtual clock): over HTTP, the record of an upload eight days old answers 410 after it.
TEST_P(RetentionTest, TheServersMaintenancePassAppliesIt) {
  ManualClock clock;
  test::ServerOptions options;
  options.clock = &clock;
  options.record_retention_days = 7;
  test::RunningServer server(GetParam(), options);
  HttpClient http(server.base_url());
  http.set_token(server.token_for("alice", Role::kTrainee));
  const HttpAnswer up = http.request("POST", "/api/v1/results", FakeRecords::make("y_bifurcation", {}, false, "http-run"));
  ASSERT_EQ(up.status, 201) << up.body;
  const std::string record = "/api/v1/results/" + std::to_string(json::parse(up.body)["id"].get<int>()) + "/record";
  server.app->maintain_once();
  EXPECT_EQ(http.get(record).status, 200);
  clock.advance_us(8 * kDayUs);
  http.set_token(server.token_for("teacher", Role::kInstructor));
  EXPECT_EQ(http.get(record).status, 200) << "kept until the pass runs";
  server.app->maintain_once();
  EXPECT_EQ(http.get(record).status, 410);
}

INSTANTIATE_TEST_SUITE_P(Backends, RetentionTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
