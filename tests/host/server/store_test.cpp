// The Store on both databases: every test runs on SQLite and on a real PostgreSQL.
#include <gtest/gtest.h>

#include <thread>

#include "server/migrations.hpp"
#include "server/store.hpp"
#include "support/backends.hpp"

namespace cathbox::server {
namespace {

using test::BackendName;
using test::kBackends;

constexpr std::int64_t kT0 = 1'700'000'000'000'000;

class StoreTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { store_ = test::fresh_store(GetParam()); }

  User make_user(const std::string& name, Role role = Role::kTrainee) {
    auto u = store_->create_user(name, role, "$argon2id$hash-of-" + name, kT0);
    EXPECT_TRUE(u.has_value());
    return *u;
  }

  CaseVersion meta(const std::string& hash) {
    CaseVersion m;
    m.title = "Title " + hash;
    m.case_file = "c.case";
    m.hclm_file = "c.hclm";
    m.content_hash = hash;
    m.raw_bytes = 1000;
    m.wire_bytes = 200;
    m.mesh_vertices = 10;
    m.mesh_triangles = 16;
    m.mesh_bytes = 432;
    return m;
  }

  ResultRow result_row(const User& u, const std::string& hash, const std::string& case_name, std::int64_t uploaded_us) {
    ResultRow r;
    r.content_hash = hash;
    r.user_id = u.id;
    r.case_name = case_name;
    r.started_us = uploaded_us - 60'000'000;
    r.duration_ms = 60'000;
    r.uploaded_us = uploaded_us;
    r.record_bytes = 5;
    r.metrics_json = R"({"procedure_time_s":60})";
    return r;
  }

  std::unique_ptr<Store> store_;
};

TEST_P(StoreTest, MigrationsReachTheLatestVersionOnceAndAreIdempotent) {
  EXPECT_EQ(schema_version(store_->database()), latest_schema_version());
  const auto again = migrate(store_->database());
  ASSERT_TRUE(again) << again.error().message;
  EXPECT_EQ(again.value().from_version, latest_schema_version());
  EXPECT_EQ(again.value().to_version, latest_schema_version());
}

TEST_P(StoreTest, MigratingStepByStepKeepsTheData) {
  std::unique_ptr<Database> db = test::fresh_database(GetParam());
  EXPECT_EQ(schema_version(*db), 0);
  const auto first = migrate(*db, 1);
  ASSERT_TRUE(first) << first.error().message;
  EXPECT_EQ(first.value().to_version, 1);
  Store early(std::move(db));
  ASSERT_TRUE(early.create_user("early", Role::kAdmin, "$argon2id$x", kT0));
  const auto rest = migrate(early.database());
  ASSERT_TRUE(rest) << rest.error().message;
  EXPECT_EQ(rest.value().from_version, 1);
  EXPECT_EQ(rest.value().to_version, latest_schema_version());
  const auto user = early.user_by_name("early");
  ASSERT_TRUE(user);
  EXPECT_EQ(user->role, Role::kAdmin);
}

TEST_P(StoreTest, ADatabaseNewerThanTheProgramIsRefusedUntouched) {
  store_->database().transact(TxMode::kWrite, [](SqlSession& s) {
    (void)s.query("INSERT INTO schema_migrations (version, name, applied_us) VALUES ($1, $2, $3)",
                  {std::int64_t{99}, std::string("from the future"), kT0});
  });
  const auto refused = migrate(store_->database());
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().status, 409);
  EXPECT_NE(refused.error().message.find("schema version 99 is newer"), std::string::npos) << refused.error().message;
}

TEST_P(StoreTest, UsersAreUniqueByNameAndUpdatable) {
  const User alice = make_user("alice");
  EXPECT_FALSE(store_->create_user("alice", Role::kAdmin, "$argon2id$other", kT0));
  const User boss = make_user("boss", Role::kAdmin);
  EXPECT_EQ(store_->count_admins(), 1);
  ASSERT_TRUE(store_->user_by_id(alice.id));
  EXPECT_EQ(store_->user_by_id(alice.id)->name, "alice");
  EXPECT_FALSE(store_->user_by_name("nobody"));
  EXPECT_TRUE(store_->update_user(alice.id, Role::kInstructor, std::string("$argon2id$new"), true));
  const auto changed = store_->user_by_name("alice");
  EXPECT_EQ(changed->role, Role::kInstructor);
  EXPECT_EQ(changed->password_hash, "$argon2id$new");
  EXPECT_TRUE(changed->disabled);
  EXPECT_FALSE(store_->update_user(alice.id + boss.id + 100, Role::kAdmin, std::nullopt, std::nullopt));
  const auto all = store_->list_users();
  ASSERT_EQ(all.size(), 2U);
  EXPECT_EQ(all[0].name, "alice");
  EXPECT_EQ(all[1].name, "boss");
}

TEST_P(StoreTest, TokensResolveToTheirOwnerUntilDeletedOrPurged) {
  const User alice = make_user("alice");
  store_->insert_token("h1", alice.id, kT0, kT0 + 100);
  store_->insert_token("h2", alice.id, kT0, kT0 + 200);
  const auto owner = store_->token_owner("h1");
  ASSERT_TRUE(owner);
  EXPECT_EQ(owner->user.name, "alice");
  EXPECT_EQ(owner->expires_us, kT0 + 100);
  EXPECT_EQ(store_->purge_tokens(kT0 + 150), 1);
  EXPECT_FALSE(store_->token_owner("h1"));
  store_->delete_user_tokens(alice.id);
  EXPECT_FALSE(store_->token_owner("h2"));
}

TEST_P(StoreTest, LoginFailuresAreCountedInAWindow) {
  store_->record_login_failure("alice", kT0);
  store_->record_login_failure("alice", kT0 + 10);
  store_->record_login_failure("bob", kT0 + 10);
  EXPECT_EQ(store_->login_failures_since("alice", kT0), 2);
  EXPECT_EQ(store_->login_failures_since("alice", kT0 + 5), 1);
  EXPECT_EQ(store_->purge_login_failures(kT0 + 5), 1);
  store_->clear_login_failures("alice");
  EXPECT_EQ(store_->login_failures_since("alice", 0), 0);
  EXPECT_EQ(store_->login_failures_since("bob", 0), 1);
}

TEST_P(StoreTest, CaseVersionsCountUpAndTheSameContentIsNotANewVersion) {
  const User boss = make_user("boss", Role::kInstructor);
  CaseVersion m = meta("hash-a");
  m.uploaded_by = boss.id;
  std::string bundle("\x28\xb5\x2f\xfd\x00\xff\x01", 7);  // binary, with NUL and high bytes
  const CaseInsert v1 = store_->insert_case_version("neuro", m, bundle, kT0);
  EXPECT_TRUE(v1.created);
  EXPECT_EQ(v1.version.version, 1);
  const CaseInsert same = store_->insert_case_version("neuro", m, bundle, kT0 + 1);
  EXPECT_FALSE(same.created);
  EXPECT_EQ(same.version.id, v1.version.id);
  const CaseInsert v2 = store_->insert_case_version("neuro", meta("hash-b"), "b", kT0 + 2);
  EXPECT_TRUE(v2.created);
  EXPECT_EQ(v2.version.version, 2);
  // Back to the first content: a third version (the newest is what counts).
  EXPECT_EQ(store_->insert_case_version("neuro", m, bundle, kT0 + 3).version.version, 3);
  (void)store_->insert_case_version("aneurysm", meta("hash-c"), "c", kT0 + 4);

  const auto listed = store_->list_cases();
  ASSERT_EQ(listed.size(), 2U);
  EXPECT_EQ(listed[0].name, "aneurysm");
  EXPECT_EQ(listed[1].name, "neuro");
  EXPECT_EQ(listed[1].version, 3);
  EXPECT_EQ(store_->case_versions("neuro").size(), 3U);
  EXPECT_EQ(store_->case_version("neuro", 0)->version, 3);
  const auto first = store_->case_version("neuro", 1);
  ASSERT_TRUE(first);
  EXPECT_EQ(first->title, "Title hash-a");
  EXPECT_EQ(first->mesh_bytes, 432);
  EXPECT_EQ(first->uploaded_by, boss.id);
  EXPECT_FALSE(store_->case_version("neuro", 4));
  EXPECT_FALSE(store_->case_version("nothing", 0));
  EXPECT_EQ(store_->case_version_by_hash("hash-b")->version, 2);
  EXPECT_EQ(store_->case_bundle(first->id), bundle);
}

TEST_P(StoreTest, ConcurrentUploadsOfOneCaseGetDistinctVersions) {
  constexpr int kThreads = 4;
  std::vector<std::thread> threads;
  std::vector<int> versions(kThreads);
  for (int i = 0; i < kThreads; ++i) {
    threads.emplace_back([&, i] { versions[static_cast<std::size_t>(i)] = store_->insert_case_version("race", meta("h" + std::to_string(i)), "x", kT0).version.version; });
  }
  for (auto& t : threads) t.join();
  std::sort(versions.begin(), versions.end());
  for (int i = 0; i < kThreads; ++i) EXPECT_EQ(versions[static_cast<std::size_t>(i)], i + 1);
}

TEST_P(StoreTest, AssignmentsNeedAnExistingCase) {
  const User alice = make_user("alice");
  const User boss = make_user("boss", Role::kInstructor);
  Assignment a;
  a.trainee_id = alice.id;
  a.case_name = "neuro";
  a.criteria_json = "[]";
  a.assigned_by = boss.id;
  EXPECT_FALSE(store_->insert_assignment(a, kT0));
  (void)store_->insert_case_version("neuro", meta("h"), "b", kT0);
  a.due_us = kT0 + 1000;
  a.note = "first try";
  const auto made = store_->insert_assignment(a, kT0);
  ASSERT_TRUE(made);
  EXPECT_EQ(made->trainee, "alice");
  EXPECT_EQ(made->case_name, "neuro");
  EXPECT_EQ(made->due_us, kT0 + 1000);
  EXPECT_EQ(store_->list_assignments(alice.id).size(), 1U);
  EXPECT_EQ(store_->list_assignments(boss.id).size(), 0U);
  EXPECT_EQ(store_->list_assignments(std::nullopt).size(), 1U);
  EXPECT_TRUE(store_->delete_assignment(made->id));
  EXPECT_FALSE(store_->delete_assignment(made->id));
  EXPECT_FALSE(store_->assignment(made->id));
}

TEST_P(StoreTest, DeletingAnAssignmentClearsItsResultsVerdictsButKeepsTheResults) {
  const User alice = make_user("alice");
  const User boss = make_user("boss", Role::kInstructor);
  (void)store_->insert_case_version("neuro", meta("h"), "b", kT0);
  Assignment a;
  a.trainee_id = alice.id;
  a.case_name = "neuro";
  a.criteria_json = "[]";
  a.assigned_by = boss.id;
  const auto made = store_->insert_assignment(a, kT0);
  ASSERT_TRUE(made);
  ResultRow run = result_row(alice, "hash-assigned", "neuro", kT0 + 10);
  run.assignment_id = made->id;
  run.passed = true;
  (void)store_->insert_result(run, {{"procedure_time_s", 60.0}}, "rec");
  ResultRow other = result_row(alice, "hash-other", "neuro", kT0 + 20);
  other.passed = false;
  (void)store_->insert_result(other, {}, "rec2");
  ASSERT_TRUE(store_->delete_assignment(made->id));
  const auto kept = store_->result_by_hash("hash-assigned");
  ASSERT_TRUE(kept);
  EXPECT_FALSE(kept->assignment_id.has_value());
  EXPECT_FALSE(kept->passed.has_value());  // no criteria left to have passed
  EXPECT_EQ(store_->result_metrics(kept->id).size(), 1U);
  EXPECT_EQ(store_->result_by_hash("hash-other")->passed, false);  // another result keeps its verdict
}

TEST_P(StoreTest, ResultsAreIdempotentByContentHashAndFilterable) {
  const User alice = make_user("alice");
  const User bob = make_user("bob");
  const std::string record("rec\0\xff\x01", 6);
  ResultRow r1 = result_row(alice, "hash1", "neuro", kT0 + 10);
  r1.passed = true;
  const ResultInsert first = store_->insert_result(r1, {{"procedure_time_s", 60.0}, {"peak_wall_force_mN", 150.5}}, record);
  EXPECT_TRUE(first.created);
  const ResultInsert again = store_->insert_result(r1, {{"procedure_time_s", 60.0}}, record);
  EXPECT_FALSE(again.created);
  EXPECT_EQ(again.row.id, first.row.id);
  EXPECT_EQ(store_->result_metrics(first.row.id).size(), 2U);
  EXPECT_EQ(store_->result_record(first.row.id), record);

  ResultRow r2 = result_row(alice, "hash2", "aneurysm", kT0 + 20);
  r2.passed = false;
  (void)store_->insert_result(r2, {{"peak_wall_force_mN", 250.0}}, "r2");
  (void)store_->insert_result(result_row(bob, "hash3", "neuro", kT0 + 30), {{"peak_wall_force_mN", 90.0}}, "r3");

  ResultFilter f;
  EXPECT_EQ(store_->list_results(f).size(), 3U);
  EXPECT_EQ(store_->list_results(f)[0].content_hash, "hash3");  // newest first
  f.user_id = alice.id;
  EXPECT_EQ(store_->list_results(f).size(), 2U);
  f.case_name = "neuro";
  EXPECT_EQ(store_->list_results(f).size(), 1U);
  ResultFilter by_metric;
  by_metric.metrics.push_back({"peak_wall_force_mN", std::nullopt, 200.0});
  EXPECT_EQ(store_->list_results(by_metric).size(), 2U);
  by_metric.metrics[0].min = 100.0;
  ASSERT_EQ(store_->list_results(by_metric).size(), 1U);
  EXPECT_EQ(store_->list_results(by_metric)[0].content_hash, "hash1");
  ResultFilter passed;
  passed.passed = false;
  ASSERT_EQ(store_->list_results(passed).size(), 1U);
  EXPECT_EQ(store_->list_results(passed)[0].content_hash, "hash2");
  ResultFilter window;
  window.since_us = kT0 + 15;
  window.until_us = kT0 + 30;
  ASSERT_EQ(store_->list_results(window).size(), 1U);
  ResultFilter page;
  page.limit = 1;
  page.offset = 1;
  ASSERT_EQ(store_->list_results(page).size(), 1U);
  EXPECT_EQ(store_->list_results(page)[0].content_hash, "hash2");
  EXPECT_EQ(store_->result_by_hash("hash2")->passed, false);
  EXPECT_FALSE(store_->result_by_hash("hash3")->passed.has_value());
}

TEST_P(StoreTest, HostileTextIsStoredAsDataNeverAsSql) {
  const std::string evil = "x'); DROP TABLE users; --";
  const User alice = make_user("alice");
  (void)store_->insert_result(result_row(alice, evil, evil, kT0), {{evil, 1.0}}, evil);
  ResultFilter f;
  f.case_name = evil;
  f.metrics.push_back({evil, 0.5, 1.5});
  const auto rows = store_->list_results(f);
  ASSERT_EQ(rows.size(), 1U);
  EXPECT_EQ(rows[0].case_name, evil);
  EXPECT_EQ(store_->list_users().size(), 1U);
  const std::string unicode = "Aneurysm — ACoA ✓ é";
  CaseVersion m = meta("u");
  m.title = unicode;
  (void)store_->insert_case_version("u", m, "b", kT0);
  EXPECT_EQ(store_->case_version("u", 0)->title, unicode);
}

TEST_P(StoreTest, LiveRigsAreClaimedPerUserAndGoStale) {
  const User alice = make_user("alice");
  const User bob = make_user("bob");
  LiveRig rig{"rig-1", alice.id, "", "neuro", 1, std::nullopt, "instance-a", kT0, kT0};
  EXPECT_TRUE(store_->claim_live_rig(rig, kT0 - 10));
  LiveRig other = rig;
  other.user_id = bob.id;
  other.instance = "instance-b";
  EXPECT_FALSE(store_->claim_live_rig(other, kT0 - 10));  // alice was seen recently
  EXPECT_EQ(store_->live_rigs(kT0).size(), 1U);
  EXPECT_EQ(store_->live_rigs(kT0)[0].user, "alice");
  store_->touch_live_rig("rig-1", "instance-a", kT0 + 100);
  EXPECT_EQ(store_->live_rig("rig-1")->last_seen_us, kT0 + 100);
  EXPECT_TRUE(store_->claim_live_rig(other, kT0 + 200));  // stale: bob takes over
  EXPECT_EQ(store_->live_rig("rig-1")->user, "bob");
  store_->end_live_rig("rig-1", "instance-a");  // not alice's instance any more: nothing
  EXPECT_TRUE(store_->live_rig("rig-1"));
  store_->end_live_rig("rig-1", "instance-b");
  EXPECT_FALSE(store_->live_rig("rig-1"));
}

TEST_P(StoreTest, LiveOverflowHoldsLargePayloadsUntilPurged) {
  const std::string big(20000, 'x');
  const std::int64_t id = store_->insert_live_overflow(big, kT0);
  EXPECT_EQ(store_->live_overflow(id), big);
  EXPECT_EQ(store_->purge_live_overflow(kT0 + 1), 1);
  EXPECT_FALSE(store_->live_overflow(id));
}

INSTANTIATE_TEST_SUITE_P(Backends, StoreTest, ::testing::ValuesIn(kBackends), BackendName());

TEST(OpenDatabase, UnknownSchemesAndBadPathsAreOneClearLine) {
  const DatabaseOpen mysql = open_database("mysql://localhost/x");
  EXPECT_FALSE(mysql.db);
  EXPECT_EQ(mysql.error, "--db: unknown database 'mysql:' (use sqlite:PATH or postgresql://...)");
  const DatabaseOpen bad = open_database("sqlite:/proc/no/such/folder/x.db");
  EXPECT_FALSE(bad.db);
  EXPECT_NE(bad.error.find("/proc/no/such"), std::string::npos) << bad.error;
  const DatabaseOpen pg = open_database("postgresql:///x?host=/nonexistent-socket-dir&user=u&password=secret");
  EXPECT_FALSE(pg.db);
  EXPECT_EQ(pg.error.find("secret"), std::string::npos) << pg.error;
}

}  // namespace
}  // namespace cathbox::server
