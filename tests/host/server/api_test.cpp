// The REST API end to end (without sockets) on SQLite and PostgreSQL: logins, tokens, users,
// the case library, assignments and results, in virtual time.
#include <gtest/gtest.h>

#include "server/case_bundle.hpp"
#include "server/sha256.hpp"
#include "server/zstd_codec.hpp"
#include "support/api_fixture.hpp"

namespace cathbox::server {
namespace {

using test::ApiFixture;
using test::error_of;
using test::FakeRecords;
using json = nlohmann::json;

using ApiTest = test::CentreTest;

TEST_P(ApiTest, LoginAnswersATokenThatExpires) {
  const json me = f_->call_json("GET", "/api/v1/me", nullptr, alice_, 200);
  EXPECT_EQ(me["name"], "alice");
  EXPECT_EQ(me["role"], "trainee");
  f_->clock.advance_us(f_->auth->options().token_lifetime_us + 1);
  const ApiResponse expired = f_->call("GET", "/api/v1/me", "", alice_);
  EXPECT_EQ(expired.status, 401);
  EXPECT_EQ(error_of(expired), "authorization: token expired (log in again)");
}

TEST_P(ApiTest, WrongPasswordsAndUnknownNamesGetTheSameLine) {
  const ApiResponse wrong = f_->call("POST", "/api/v1/login", R"({"name":"alice","password":"nope-nope"})");
  const ApiResponse unknown = f_->call("POST", "/api/v1/login", R"({"name":"mallory","password":"nope-nope"})");
  EXPECT_EQ(wrong.status, 401);
  EXPECT_EQ(unknown.status, 401);
  EXPECT_EQ(error_of(wrong), error_of(unknown));
}

TEST_P(ApiTest, RepeatedFailedLoginsAreThrottledPerAccountAndAddressUntilTheWindowPasses) {
  for (int i = 0; i < f_->auth->options().max_failures; ++i) {
    EXPECT_EQ(f_->call("POST", "/api/v1/login", R"({"name":"alice","password":"wrong-one"})", "", "10.9.9.9").status, 401);
  }
  // Even the right password is refused now, from that address.
  const ApiResponse throttled = f_->call("POST", "/api/v1/login", R"({"name":"alice","password":"password-123"})", "", "10.9.9.9");
  EXPECT_EQ(throttled.status, 429);
  EXPECT_NE(error_of(throttled).find("too many failed attempts"), std::string::npos);
  // Retry-After says the same as the line: the account's window, not the address's minute.
  std::string retry_after;
  for (const auto& [name, value] : throttled.headers) {
    if (name == "Retry-After") retry_after = value;
  }
  EXPECT_EQ(retry_after, std::to_string(f_->auth->options().failure_window_us / 1'000'000));
  // Other accounts are not affected.
  EXPECT_EQ(f_->call("POST", "/api/v1/login", R"({"name":"bob","password":"password-123"})", "", "10.9.9.8").status, 200);
  f_->clock.advance_us(f_->auth->options().failure_window_us + 1);
  EXPECT_EQ(f_->call("POST", "/api/v1/login", R"({"name":"alice","password":"password-123"})", "", "10.9.9.9").status, 200);
}

TEST_P(ApiTest, OneAddressIsThrottledAcrossAccounts) {
  int refused = 0;
  for (int i = 0; i < 40; ++i) {
    const ApiResponse r = f_->call("POST", "/api/v1/login", json{{"name", "user" + std::to_string(i)}, {"password", "x-x-x-x-x"}}.dump(), "", "192.0.2.7");
    if (r.status == 429) ++refused;
  }
  EXPECT_EQ(refused, 40 - f_->auth->options().address_burst);
  // A minute later the bucket has refilled.
  f_->clock.advance_us(60'000'000);
  EXPECT_EQ(f_->call("POST", "/api/v1/login", R"({"name":"alice","password":"password-123"})", "", "192.0.2.7").status, 200);
}

TEST_P(ApiTest, LogoutEndsTheToken) {
  EXPECT_EQ(f_->call("POST", "/api/v1/logout", "", alice_).status, 204);
  EXPECT_EQ(f_->call("GET", "/api/v1/me", "", alice_).status, 401);
}

TEST_P(ApiTest, AdminsManageUsersAndTheLastAdminStays) {
  const json made = f_->call_json("POST", "/api/v1/users", {{"name", "carol"}, {"role", "instructor"}, {"password", "long-enough"}}, admin_, 201);
  EXPECT_EQ(made["role"], "instructor");
  EXPECT_EQ(f_->call("POST", "/api/v1/users", json{{"name", "carol"}, {"role", "trainee"}, {"password", "long-enough"}}.dump(), admin_).status, 409);
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/users", json{{"name", "dave"}, {"role", "boss"}, {"password", "long-enough"}}.dump(), admin_)),
            "field 'role': expected trainee, instructor or admin");
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/users", json{{"name", "dave"}, {"role", "trainee"}, {"password", "short"}}.dump(), admin_)),
            "password: at least 8 characters");
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/users", json{{"name", "Dave!"}, {"role", "trainee"}, {"password", "long-enough"}}.dump(), admin_))
                .rfind("user name", 0),
            0U);
  const ApiResponse last = f_->call("PATCH", "/api/v1/users/root", R"({"role":"trainee"})", admin_);
  EXPECT_EQ(last.status, 409);
  EXPECT_EQ(error_of(last), "'root' is the last admin");
  // Disabling ends the account's sessions and logins.
  const std::string carol = f_->login("carol", "long-enough");
  f_->call_json("PATCH", "/api/v1/users/carol", {{"disabled", true}}, admin_, 200);
  EXPECT_EQ(f_->call("GET", "/api/v1/me", "", carol).status, 401);
  EXPECT_EQ(f_->call("POST", "/api/v1/login", R"({"name":"carol","password":"long-enough"})").status, 401);
  const json users = f_->call_json("GET", "/api/v1/users", nullptr, teacher_, 200);
  EXPECT_EQ(users["users"].size(), 5U);
}

TEST_P(ApiTest, ChangingOnesPasswordNeedsTheOldOneAndEndsOtherSessions) {
  EXPECT_EQ(f_->call("POST", "/api/v1/me/password", R"({"old_password":"wrong-wrong","new_password":"new-password"})", alice_).status, 403);
  EXPECT_EQ(f_->call("POST", "/api/v1/me/password", R"({"old_password":"password-123","new_password":"new-password"})", alice_).status, 204);
  EXPECT_EQ(f_->call("GET", "/api/v1/me", "", alice_).status, 401);
  EXPECT_FALSE(f_->login("alice", "new-password").empty());
}

TEST_P(ApiTest, GuessingTheOldPasswordWithATokenIsThrottledLikeLogins) {
  const std::string wrong = R"({"old_password":"wrong-wrong","new_password":"new-password"})";
  for (int i = 0; i < f_->auth->options().max_failures; ++i) {
    EXPECT_EQ(f_->call("POST", "/api/v1/me/password", wrong, alice_).status, 403);
  }
  // Now even the right one waits for the window, and so do logins to the account.
  const std::string right = R"({"old_password":"password-123","new_password":"new-password"})";
  EXPECT_EQ(f_->call("POST", "/api/v1/me/password", right, alice_).status, 429);
  EXPECT_EQ(f_->call("POST", "/api/v1/login", R"({"name":"alice","password":"password-123"})", "", "10.0.0.1").status, 429);
  f_->clock.advance_us(f_->auth->options().failure_window_us + 1);
  EXPECT_EQ(f_->call("POST", "/api/v1/me/password", right, alice_).status, 204);
}

TEST_P(ApiTest, CasesUploadValidateVersionAndDownloadCompressed) {
  const ApiResponse first = f_->upload_bundled_case("y_bifurcation", "ybif", teacher_);
  ASSERT_EQ(first.status, 201) << first.body;
  const json v1 = json::parse(first.body);
  EXPECT_EQ(v1["version"], 1);
  EXPECT_EQ(v1["created"], true);
  EXPECT_GT(v1["sizes"]["mesh_triangles"].get<int>(), 1000);
  EXPECT_LT(v1["sizes"]["wire_bytes"].get<int>(), v1["sizes"]["raw_bytes"].get<int>());
  const ApiResponse again = f_->upload_bundled_case("y_bifurcation", "ybif", teacher_);
  EXPECT_EQ(again.status, 200);
  EXPECT_EQ(json::parse(again.body)["version"], 1);
  // An edited case is version 2.
  json edited = {{"name", "ybif"},
                 {"case_file", "y_bifurcation.case"},
                 {"case", test::source_file("cases/y_bifurcation.case") + "\n# edited\n"},
                 {"hclm_file", "y_bifurcation.hclm"},
                 {"hclm", test::source_file("cases/y_bifurcation.hclm")}};
  EXPECT_EQ(f_->call_json("POST", "/api/v1/cases", edited, admin_, 201)["version"], 2);
  const json versions = f_->call_json("GET", "/api/v1/cases/ybif", nullptr, alice_, 200);
  EXPECT_EQ(versions["versions"].size(), 2U);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/cases/ybif/versions/latest", nullptr, alice_, 200)["version"], 2);

  // Download: zstd when accepted, the same JSON as identity otherwise, 304 on a matching ETag.
  ApiRequest get;
  get.method = "GET";
  get.target = "/api/v1/cases/ybif/versions/1/bundle";
  get.authorization = "Bearer " + alice_;
  get.accept_encoding = "gzip, zstd";
  const ApiResponse zst = f_->api->handle(get);
  ASSERT_EQ(zst.status, 200);
  const auto encoding = std::find(zst.headers.begin(), zst.headers.end(), std::make_pair(std::string("Content-Encoding"), std::string("zstd")));
  EXPECT_NE(encoding, zst.headers.end());
  const Result<std::string> plain = zstd_decompress(zst.body, kMaxBundleBytes);
  ASSERT_TRUE(plain);
  EXPECT_EQ(sha256_hex(plain.value()), v1["content_hash"]);
  const Result<CaseBundle> bundle = parse_bundle_json(plain.value());
  ASSERT_TRUE(bundle);
  EXPECT_EQ(bundle.value().hclm_text, test::source_file("cases/y_bifurcation.hclm"));
  get.accept_encoding = "zstd;q=0";
  EXPECT_EQ(f_->api->handle(get).body, plain.value());
  get.if_none_match = "\"" + v1["content_hash"].get<std::string>() + "\"";
  EXPECT_EQ(f_->api->handle(get).status, 304);
}

TEST_P(ApiTest, BadCaseFilesAreRefusedWithTheReadersLine) {
  json body = {{"name", "bad"}, {"case_file", "y.case"}, {"case", test::source_file("cases/y_bifurcation.case")}, {"hclm_file", "y_bifurcation.hclm"}};
  std::string hclm = test::source_file("cases/y_bifurcation.hclm");
  // A negative radius on the first vertex line.
  const std::size_t v = hclm.find("\nv ");
  const std::size_t line = static_cast<std::size_t>(std::count(hclm.begin(), hclm.begin() + static_cast<long>(v), '\n')) + 2;
  const std::size_t end = hclm.find('\n', v + 1);
  std::string broken = hclm.substr(0, v + 1) + "v 0 0 0 -3" + hclm.substr(end);
  body["hclm"] = broken;
  const ApiResponse r = f_->call("POST", "/api/v1/cases", body.dump(), teacher_);
  EXPECT_EQ(r.status, 422);
  EXPECT_EQ(error_of(r).rfind("y_bifurcation.hclm:" + std::to_string(line) + ": ", 0), 0U) << error_of(r);

  body["hclm"] = hclm;
  body["case"] = "cathbox-case 1\nname x\nvessel y_bifurcation.hclm\nfrobnicate 3\n";
  const ApiResponse bad_case = f_->call("POST", "/api/v1/cases", body.dump(), teacher_);
  EXPECT_EQ(bad_case.status, 422);
  EXPECT_EQ(error_of(bad_case).rfind("y.case:4: ", 0), 0U) << error_of(bad_case);

  body["case"] = "cathbox-case 1\nname x\nvessel other.hclm\n";
  const ApiResponse wrong_vessel = f_->call("POST", "/api/v1/cases", body.dump(), teacher_);
  EXPECT_EQ(wrong_vessel.status, 422);
  EXPECT_EQ(error_of(wrong_vessel), "y.case:3: vessel 'other.hclm' is not the uploaded HCLM file 'y_bifurcation.hclm' (give its plain name)");

  body["case"] = "cathbox-case 1\nname x\nvessel y_bifurcation.hclm\ntarget 99 0.5\n";
  const ApiResponse no_target = f_->call("POST", "/api/v1/cases", body.dump(), teacher_);
  EXPECT_EQ(no_target.status, 422);
  EXPECT_EQ(error_of(no_target), "y.case:4: target segment 99 is not a segment of y_bifurcation.hclm");
  EXPECT_EQ(f_->call_json("GET", "/api/v1/cases", nullptr, teacher_, 200)["cases"].size(), 0U);
}

TEST_P(ApiTest, AssignmentsCarryCheckedCriteria) {
  ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  const json criteria = json::array({{{"metric", "target_reached"}, {"op", "=="}, {"value", 1}},
                                     {{"metric", "fluoroscopy_time_s"}, {"op", "<="}, {"value", 180}},
                                     {{"metric", "peak_wall_force_mN"}, {"op", "<="}, {"value", 200}}});
  const json a = f_->call_json("POST", "/api/v1/assignments", {{"trainee", "alice"}, {"case", "ybif"}, {"criteria", criteria}, {"due_at", "2030-01-31"}}, teacher_, 201);
  EXPECT_EQ(a["criteria"].size(), 3U);
  EXPECT_EQ(a["due_at"], "2030-01-31T00:00:00.000000Z");
  EXPECT_EQ(a["case_version"], "latest");
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/assignments", json{{"trainee", "alice"}, {"case", "ybif"}, {"criteria", json::array({{{"metric", "target_reached"}, {"op", "=<"}, {"value", 1}}})}}.dump(), teacher_)),
            "field 'criteria[0].op': '=<' is not one of < <= == >= >");
  EXPECT_EQ(error_of(f_->call("POST", "/api/v1/assignments", json{{"trainee", "alice"}, {"case", "ybif"}, {"criteria", json::array({{{"metric", "speed"}, {"op", "<"}, {"value", 1}}})}}.dump(), teacher_))
                .rfind("field 'criteria[0].metric': unknown metric 'speed'", 0),
            0U);
  EXPECT_EQ(f_->call("POST", "/api/v1/assignments", json{{"trainee", "zed"}, {"case", "ybif"}}.dump(), teacher_).status, 404);
  EXPECT_EQ(f_->call("POST", "/api/v1/assignments", json{{"trainee", "alice"}, {"case", "nope"}}.dump(), teacher_).status, 404);
  // Trainees see their own.
  EXPECT_EQ(f_->call_json("GET", "/api/v1/assignments", nullptr, alice_, 200)["assignments"].size(), 1U);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/assignments", nullptr, bob_, 200)["assignments"].size(), 0U);
  EXPECT_EQ(f_->call("GET", "/api/v1/assignments/" + std::to_string(a["id"].get<int>()), "", bob_).status, 404);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/assignments?trainee=alice", nullptr, teacher_, 200)["assignments"].size(), 1U);
  EXPECT_EQ(f_->call("DELETE", "/api/v1/assignments/" + std::to_string(a["id"].get<int>()), "", alice_).status, 403);
  EXPECT_EQ(f_->call("DELETE", "/api/v1/assignments/" + std::to_string(a["id"].get<int>()), "", teacher_).status, 204);
}

TEST_P(ApiTest, ResultsAreCheckedIdempotentEvaluatedAndPrivate) {
  ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  const json a = f_->call_json("POST", "/api/v1/assignments",
                               {{"trainee", "alice"}, {"case", "ybif"},
                                {"criteria", json::array({{{"metric", "target_reached"}, {"op", "=="}, {"value", 1}},
                                                          {{"metric", "peak_wall_force_mN"}, {"op", "<="}, {"value", 200}}})}},
                               teacher_, 201);
  const std::string target = "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>());
  const std::string good = FakeRecords::make("y_bifurcation", {{"target_reached", 1}, {"peak_wall_force_mN", 150}});
  const std::string bad = FakeRecords::make("y_bifurcation", {{"target_reached", 1}, {"peak_wall_force_mN", 250}});
  const ApiResponse stored = f_->call("POST", target, good, alice_);
  ASSERT_EQ(stored.status, 201) << stored.body;
  const json r1 = json::parse(stored.body);
  EXPECT_EQ(r1["passed"], true);
  EXPECT_EQ(r1["case"], "ybif");
  EXPECT_EQ(r1["created"], true);
  // The same bytes again: the stored result, not a second one.
  const ApiResponse again = f_->call("POST", target, good, alice_);
  EXPECT_EQ(again.status, 200);
  EXPECT_EQ(json::parse(again.body)["id"], r1["id"]);
  EXPECT_EQ(f_->call("POST", "/api/v1/results", good, bob_).status, 409);
  EXPECT_EQ(json::parse(f_->call("POST", target, bad, alice_).body)["passed"], false);
  const ApiResponse tampered = f_->call("POST", target, FakeRecords::make("y_bifurcation", {}, true), alice_);
  EXPECT_EQ(tampered.status, 422);
  EXPECT_EQ(error_of(tampered), "record: tick 1200: state hash differs (tampered or broken)");
  // Bob cannot file under Alice's assignment, nor read her results.
  EXPECT_EQ(f_->call("POST", target, FakeRecords::make("y_bifurcation", {}, false, "bob"), bob_).status, 404);
  const std::string id = std::to_string(r1["id"].get<int>());
  EXPECT_EQ(f_->call("GET", "/api/v1/results/" + id, "", bob_).status, 404);  // as if it did not exist
  EXPECT_EQ(f_->call("GET", "/api/v1/results/" + id + "/record", "", bob_).status, 404);
  EXPECT_EQ(f_->call("GET", "/api/v1/results?trainee=alice", "", bob_).status, 403);
  // The same answer for a name with no account: a trainee cannot probe which accounts exist.
  const ApiResponse probe = f_->call("GET", "/api/v1/results?trainee=no-such-trainee", "", bob_);
  EXPECT_EQ(probe.status, 403);
  EXPECT_EQ(probe.body.find("no-such-trainee"), std::string::npos);
  EXPECT_EQ(f_->call("GET", "/api/v1/results?trainee=bob", "", bob_).status, 200);
  EXPECT_EQ(f_->call("GET", "/api/v1/results?trainee=no-such-trainee", "", teacher_).status, 404);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results", nullptr, bob_, 200)["results"].size(), 0U);
  // Alice and her instructor can.
  const json detail = f_->call_json("GET", "/api/v1/results/" + id, nullptr, teacher_, 200);
  EXPECT_EQ(detail["evaluation"]["passed"], true);
  EXPECT_EQ(detail["evaluation"]["criteria"][1]["actual"], 150.0);
  EXPECT_EQ(f_->call("GET", "/api/v1/results/" + id + "/record", "", alice_).body, good);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results?trainee=alice&max.peak_wall_force_mN=200", nullptr, teacher_, 200)["results"].size(), 1U);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results?passed=false", nullptr, teacher_, 200)["results"].size(), 1U);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/results?case=ybif&limit=1", nullptr, alice_, 200)["results"].size(), 1U);
  EXPECT_EQ(error_of(f_->call("GET", "/api/v1/results?limit=0", "", alice_)), "query 'limit': expected an integer 1..1000");
  EXPECT_EQ(error_of(f_->call("GET", "/api/v1/results?colour=red", "", alice_)).rfind("query 'colour': unknown", 0), 0U);
  EXPECT_EQ(f_->call_json("GET", "/api/v1/assignments/" + std::to_string(a["id"].get<int>()), nullptr, alice_, 200)["results"].size(), 2U);
}

TEST_P(ApiTest, RecordsForAnotherCaseThanTheAssignmentsAreRefused) {
  ASSERT_EQ(f_->upload_bundled_case("y_bifurcation", "ybif", teacher_).status, 201);
  const json a = f_->call_json("POST", "/api/v1/assignments", {{"trainee", "alice"}, {"case", "ybif"}}, teacher_, 201);
  const ApiResponse r = f_->call("POST", "/api/v1/results?assignment=" + std::to_string(a["id"].get<int>()),
                                 FakeRecords::make("neuro", {{"target_reached", 1}}), alice_);
  EXPECT_EQ(r.status, 422);
  EXPECT_EQ(error_of(r), "record: header field 'case_text' (neuro.case) is not the assignment's case 'ybif' version 1 (by content hash)");
}

TEST_P(ApiTest, UnknownEndpointsAndMethods) {
  EXPECT_EQ(f_->call("GET", "/api/v1/nothing", "", alice_).status, 404);
  const ApiResponse r = f_->call("PUT", "/api/v1/cases", "", alice_);
  EXPECT_EQ(r.status, 405);
  EXPECT_EQ(error_of(r), "PUT is not allowed on /api/v1/cases (allowed: GET, POST)");
  EXPECT_EQ(f_->call("GET", "/api/v2/cases", "", alice_).status, 404);
}

INSTANTIATE_TEST_SUITE_P(Backends, ApiTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
