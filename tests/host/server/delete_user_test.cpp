// DELETE /api/v1/users/{name} on SQLite and PostgreSQL: the account and every result, record,
// metric, assignment, token and login failure of theirs go in one transaction, the traces
// derived from their records leave the cache; afterwards no endpoint answers anything of theirs
// (an instructor sees 404s, lists without them); admins only, not oneself; audited.
#include <gtest/gtest.h>

#include "support/api_fixture.hpp"

namespace cathbox::server {
namespace {

using test::error_of;
using test::FakeRecords;
using json = nlohmann::json;

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

INSTANTIATE_TEST_SUITE_P(Backends, DeleteUserTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
