// Bad input and roles, on both databases: every malformed body, hostile query and oversized
// field gets a 4xx with one line, never a 5xx; roles are enforced on the server.
#include <gtest/gtest.h>

#include "support/api_fixture.hpp"

namespace cathbox::server {
namespace {

using test::ApiFixture;
using test::error_of;
using json = nlohmann::json;

class SecurityTest : public test::CentreTest {
 protected:
  void SetUp() override {
    CentreTest::SetUp();
    ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  }

  // A 4xx with one non-empty line.
  void expect_clean_refusal(const ApiResponse& r, const std::string& what) {
    EXPECT_GE(r.status, 400) << what << ": " << r.body;
    EXPECT_LT(r.status, 500) << what << ": " << r.body;
    const std::string line = error_of(r);
    EXPECT_FALSE(line.empty()) << what << ": " << r.body;
    EXPECT_EQ(line.find('\n'), std::string::npos) << what;
  }
};

TEST_P(SecurityTest, MalformedJsonIsOneLineNever5xx) {
  const std::vector<std::string> bodies = {
      "",
      "{",
      "}",
      "[]",
      "null",
      "42",
      "\"text\"",
      "{\"name\":}",
      "{\"name\":\"a\",}",
      "{'name':'a'}",
      std::string(40, '[') + std::string(40, ']'),
      std::string(10000, '{'),
      "{\"name\":\"a\\u0000b\",\"password\":\"x\"}",
      "{\"name\":\"\xff\xfe\",\"password\":\"x\"}",
      "{\"name\":1e99999,\"password\":\"x\"}",
      "{\"name\":-1e400}",
      "{\"name\":12345678901234567890123,\"password\":\"x\"}",
      "{\"name\":[\"a\"],\"password\":{}}",
      "{\"name\":\"a\",\"password\":\"b\",\"admin\":true}",
      std::string("{\"name\":\"a\0b\"}", 14),
  };
  const std::vector<std::pair<std::string, std::string>> endpoints = {
      {"POST", "/api/v1/login"},       {"POST", "/api/v1/users"},       {"PATCH", "/api/v1/users/alice"},
      {"POST", "/api/v1/cases"},       {"POST", "/api/v1/assignments"}, {"POST", "/api/v1/me/password"}};
  for (const auto& [method, target] : endpoints) {
    for (const std::string& body : bodies) {
      const std::string token = target == "/api/v1/login" ? "" : admin_;
      expect_clean_refusal(f_->call(method, target, body, token), method + " " + target + " <" + body.substr(0, 30) + ">");
    }
  }
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/login", "{\"name\":1e99999}")), "body: invalid JSON: number overflow parsing '1e99999'");
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/login", std::string(40, '['))), "body: nested deeper than 32 levels at byte 32");
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/login", R"({"name":"a","password":"b","admin":true})")), "field 'admin': unknown field");
}

TEST_P(SecurityTest, HostileQueriesAndPathsAreData) {
  const std::vector<std::string> targets = {
      "/api/v1/results?trainee=x%27%3B%20DROP%20TABLE%20users%3B--",
      "/api/v1/results?case=%27%20OR%201%3D1--",
      "/api/v1/results?min.x%27%20OR%201%3D1=1",
      "/api/v1/results?since=2024-13-45",
      "/api/v1/results?until=yesterday",
      "/api/v1/results?limit=99999999999999999999",
      "/api/v1/results?offset=-1",
      "/api/v1/results?passed=maybe",
      "/api/v1/results?min.peak=abc",
      "/api/v1/results?assignment=1%20OR%201",
      "/api/v1/results/1%20OR%201=1",
      "/api/v1/results/-1",
      "/api/v1/results/99999999999999999999999",
      "/api/v1/cases/%ff%fe/versions/latest",
      "/api/v1/cases/ybif/versions/0",
      "/api/v1/cases/ybif/versions/-3",
      "/api/v1/cases/ybif/versions/1e3",
      "/api/v1/cases/..%2f..%2fetc/versions/1",
      "/api/v1/cases/ybif%00/versions/1",
      "/api/v1/assignments?trainee=%00",
      "/api/v1/assignments/abc",
      "/api/v1/cases/ybif/versions/latest/bundle/extra",
      "/api/v1/results?trainee=" + std::string(5000, 'a'),
  };
  for (const std::string& t : targets) {
    const ApiResponse r = f_->call("GET", t, "", admin_);
    EXPECT_LT(r.status, 500) << t << ": " << r.body;
  }
  // The tables are still there.
  EXPECT_EQ(f_->call_json("GET", "/api/v1/users", nullptr, admin_, 200)["users"].size(), 4U);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/cases", nullptr, admin_, 200)["cases"].size(), 1U);
}

TEST_P(SecurityTest, SizeLimitsHoldOnEveryField) {
  json big_case = {{"name", "big"}, {"case_file", "b.case"}, {"case", std::string(kMaxCaseTextBytes + 1, '#')}};
  expect_clean_refusal(f_->call("POST", "/api/v1/cases", big_case.dump(), teacher_), "case text over the limit");
  json big_hclm = {{"name", "big"}, {"case_file", "b.case"}, {"case", "cathbox-case 1\nname b\nvessel b.hclm\n"},
                   {"hclm_file", "b.hclm"}, {"hclm", std::string(kMaxHclmBytes + 1, ' ')}};
  expect_clean_refusal(f_->call("POST", "/api/v1/cases", big_hclm.dump(), teacher_), "HCLM over the limit");
  expect_clean_refusal(f_->call("POST", "/api/v1/users", json{{"name", std::string(65, 'a')}, {"role", "trainee"}, {"password", "long-enough"}}.dump(), admin_),
                       "long user name");
  expect_clean_refusal(f_->call("POST", "/api/v1/users", json{{"name", "zed"}, {"role", "trainee"}, {"password", std::string(300, 'p')}}.dump(), admin_),
                       "long password");
  json many = json::array();
  for (int i = 0; i < 40; ++i) many.push_back({{"metric", "wall_contacts"}, {"op", "<"}, {"value", i}});
  expect_clean_refusal(f_->call("POST", "/api/v1/assignments", json{{"trainee", "alice"}, {"case", "ybif"}, {"criteria", many}}.dump(), teacher_),
                       "too many criteria");
  expect_clean_refusal(f_->call("POST", "/api/v1/assignments", json{{"trainee", "alice"}, {"case", "ybif"}, {"note", std::string(3000, 'n')}}.dump(), teacher_),
                       "long note");
  // The HTTP layer refuses bodies over these before reading them (http_test); the limits are:
  EXPECT_EQ(Api::body_limit("POST", "/api/v1/login"), kMaxJsonBodyBytes);
  EXPECT_EQ(Api::body_limit("POST", "/api/v1/cases"), kMaxCaseUploadBytes);
  EXPECT_EQ(Api::body_limit("POST", "/api/v1/results?assignment=1"), kMaxRecordBytes);
}

TEST_P(SecurityTest, MalformedHclmAndCaseFilesAreRefusedWithFileAndLine) {
  const std::vector<std::pair<std::string, std::string>> bad_hclm = {
      {"s 1\ng 1\nn 2\nv 0 0 0 1\n", "y.hclm:2: segment 1 has no 'p' line"},
      {"s 1\ng 1\nn 2\nv 0 0 0 1\nv 0 0 zero 1\n", "y.hclm:5: z 'zero' is not a number"},
      {"", "y.hclm:1: missing 's' line"},
      {"s 99999999999\n", "y.hclm:1: segment count '99999999999' is not a count"},
      {std::string("s 1\ng 1\0\n", 9), "body: a string holds a NUL character"},
  };
  for (const auto& [hclm, prefix] : bad_hclm) {
    const json body = {{"name", "bad"}, {"case_file", "y.case"}, {"case", "cathbox-case 1\nname y\nvessel y.hclm\n"}, {"hclm_file", "y.hclm"}, {"hclm", hclm}};
    const ApiResponse r = f_->call("POST", "/api/v1/cases", body.dump(), teacher_);
    expect_clean_refusal(r, "hclm <" + hclm.substr(0, 20) + ">");
    EXPECT_EQ(error_of(r).rfind(prefix, 0), 0U) << error_of(r);
  }
  for (const std::string& text : {std::string("not a case"), std::string("cathbox-case 99\n"), std::string("cathbox-case 1\ntube 1 2 3\n")}) {
    const json body = {{"name", "bad"}, {"case_file", "y.case"}, {"case", text}};
    const ApiResponse r = f_->call("POST", "/api/v1/cases", body.dump(), teacher_);
    expect_clean_refusal(r, "case <" + text + ">");
    EXPECT_EQ(error_of(r).rfind("y.case:", 0), 0U) << error_of(r);
  }
}

TEST_P(SecurityTest, MalformedRecordsAreRefusedNever5xx) {
  for (const std::string& record : {std::string("x"), std::string(1000, '\0'), std::string("{\"tampered\":true}"), std::string("\x28\xb5\x2f\xfd", 4)}) {
    const ApiResponse r = f_->call("POST", "/api/v1/results", record, alice_);
    expect_clean_refusal(r, "record");
  }
  expect_clean_refusal(f_->call("POST", "/api/v1/results", "", alice_), "empty record");
}

TEST_P(SecurityTest, RolesAreEnforcedOnTheServer) {
  // What a trainee may not do, each with its 403 line.
  const std::vector<std::tuple<std::string, std::string, std::string>> forbidden = {
      {"GET", "/api/v1/users", ""},
      {"POST", "/api/v1/users", R"({"name":"eve","role":"admin","password":"long-enough"})"},
      {"PATCH", "/api/v1/users/alice", R"({"role":"admin"})"},
      {"POST", "/api/v1/cases", R"({"name":"x","case_file":"x.case","case":"cathbox-case 1\n"})"},
      {"POST", "/api/v1/assignments", R"({"trainee":"alice","case":"ybif"})"},
      {"DELETE", "/api/v1/assignments/1", ""},
  };
  for (const auto& [method, target, body] : forbidden) {
    const ApiResponse r = f_->call(method, target, body, alice_);
    EXPECT_EQ(r.status, 403) << method << " " << target << ": " << r.body;
  }
  // An instructor may not manage accounts either.
  EXPECT_EQ(f_->call("POST", "/api/v1/users", R"({"name":"eve","role":"admin","password":"long-enough"})", teacher_).status, 403);
  EXPECT_EQ(f_->call("PATCH", "/api/v1/users/alice", R"({"role":"admin"})", teacher_).status, 403);
  // Alice is still a trainee.
  EXPECT_EQ(f_->call_json("GET", "/api/v1/me", nullptr, alice_, 200)["role"], "trainee");
}

INSTANTIATE_TEST_SUITE_P(Backends, SecurityTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
