// The audit log on SQLite and PostgreSQL: the admin and instructor actions (users, cases,
// assignments) each leave who, when, what and from where; only admins read it; a trainee's or a
// refused action leaves nothing; its filters and bad input are one line each.
#include <gtest/gtest.h>

#include "server/iso_time.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server {
namespace {

using test::error_of;
using json = nlohmann::json;

using AuditTest = test::CentreTest;

TEST_P(AuditTest, AdminAndInstructorActionsAreLoggedWithWhoWhenWhatAndWhere) {
  const std::int64_t t0 = f_->clock.now_us();
  f_->call_json("POST", "/api/v1/users", {{"name", "carol"}, {"role", "instructor"}, {"password", "long-enough"}}, admin_, 201);
  f_->clock.advance_us(1'000'000);
  f_->call_json("PATCH", "/api/v1/users/carol", {{"disabled", true}, {"role", "trainee"}}, admin_, 200);
  f_->clock.advance_us(1'000'000);
  ASSERT_EQ(f_->call("POST", "/api/v1/assignments", json{{"trainee", "alice"}, {"case", "none"}}.dump(), teacher_, "10.0.0.7").status, 404);
  ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 200);  // the same content: no new version, no entry
  const ApiResponse made = f_->call("POST", "/api/v1/assignments", json{{"trainee", "alice"}, {"case", "ybif"}}.dump(), teacher_, "10.0.0.7");
  ASSERT_EQ(made.status, 201);
  const std::string id = std::to_string(json::parse(made.body)["id"].get<std::int64_t>());
  f_->clock.advance_us(1'000'000);
  EXPECT_EQ(f_->call("DELETE", "/api/v1/assignments/" + id, "", teacher_, "10.0.0.8").status, 204);
  // Refused and trainee actions leave nothing.
  EXPECT_EQ(f_->call("POST", "/api/v1/users", json{{"name", "eve"}, {"role", "admin"}, {"password", "long-enough"}}.dump(), alice_).status, 403);
  EXPECT_EQ(f_->call("DELETE", "/api/v1/assignments/" + id, "", teacher_).status, 404);

  const json log = f_->call_json("GET", "/api/v1/audit", nullptr, admin_, 200);
  ASSERT_EQ(log["entries"].size(), 5U) << log.dump();
  const json& newest = log["entries"][0];
  EXPECT_EQ(newest["action"], "assignment.delete");
  EXPECT_EQ(newest["actor"], "teacher");
  EXPECT_EQ(newest["target"], id);
  EXPECT_EQ(newest["from"], "10.0.0.8");
  EXPECT_EQ(newest["at"], iso_time(t0 + 3'000'000));
  EXPECT_EQ(log["entries"][1]["action"], "assignment.create");
  EXPECT_EQ(log["entries"][1]["detail"], "trainee=alice case=ybif");
  EXPECT_EQ(log["entries"][1]["from"], "10.0.0.7");
  EXPECT_EQ(log["entries"][2]["action"], "case.upload");
  EXPECT_EQ(log["entries"][2]["detail"], "version=1");
  EXPECT_EQ(log["entries"][3]["action"], "user.update");
  EXPECT_EQ(log["entries"][3]["target"], "carol");
  EXPECT_EQ(log["entries"][3]["detail"], "role=trainee disabled=true");
  const json& oldest = log["entries"][4];
  EXPECT_EQ(oldest["action"], "user.create");
  EXPECT_EQ(oldest["actor"], "root");
  EXPECT_EQ(oldest["detail"], "role=instructor");
  EXPECT_EQ(oldest["from"], "10.0.0.1");
  EXPECT_EQ(oldest["at"], iso_time(t0));

  // Filters: by actor, a limit (newest first), a start time.
  EXPECT_EQ(f_->call_json("GET", "/api/v1/audit?actor=root", nullptr, admin_, 200)["entries"].size(), 2U);
  const json one = f_->call_json("GET", "/api/v1/audit?limit=1", nullptr, admin_, 200);
  ASSERT_EQ(one["entries"].size(), 1U);
  EXPECT_EQ(one["entries"][0]["action"], "assignment.delete");
  EXPECT_EQ(f_->call_json("GET", "/api/v1/audit?since=" + iso_time(t0 + 1'000'000), nullptr, admin_, 200)["entries"].size(), 4U);
}

TEST_P(AuditTest, OnlyAdminsReadItAndBadQueriesAreOneLine) {
  EXPECT_EQ(f_->call("GET", "/api/v1/audit", "", teacher_).status, 403);
  EXPECT_EQ(f_->call("GET", "/api/v1/audit", "", alice_).status, 403);
  EXPECT_EQ(f_->call("GET", "/api/v1/audit").status, 401);
  const ApiResponse bad_since = f_->call("GET", "/api/v1/audit?since=yesterday", "", admin_);
  EXPECT_EQ(bad_since.status, 400);
  EXPECT_EQ(error_of(bad_since), "query 'since': expected YYYY-MM-DD or YYYY-MM-DDTHH:MM:SSZ");
  EXPECT_EQ(f_->call("GET", "/api/v1/audit?limit=0", "", admin_).status, 400);
  EXPECT_EQ(f_->call("GET", "/api/v1/audit?limit=1001", "", admin_).status, 400);
}

INSTANTIATE_TEST_SUITE_P(Backends, AuditTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
