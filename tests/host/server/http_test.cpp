// The server over real sockets on SQLite and PostgreSQL: static files, limits, malformed HTTP,
// WebSocket streaming and watching, roles on the live endpoints.
#include <gtest/gtest.h>

#include <filesystem>

#include "server/live_schema.hpp"
#include "support/server_fixture.hpp"

namespace cathbox::server {
namespace {

using json = nlohmann::json;
using test::raw_exchange;
using test::RunningServer;

std::string frame(int seq, std::size_t nodes = 8) {
  json f = {{"type", "frame"}, {"seq", seq}, {"t_ms", seq * 33.3}, {"tip_mm", {1.0, 2.0, 3.0}}};
  json pts = json::array();
  for (std::size_t i = 0; i < nodes; ++i) pts.push_back({0.5 * static_cast<double>(i), 1.25, -3.0});
  f["tools"] = json::array({{{"name", "guidewire"}, {"nodes_mm", pts}}});
  f["forces"] = {{"tip_mN", 12.5}, {"wall_peak_mN", 40.0}};
  f["fluoro"] = {{"on", false}, {"time_s", 1.5}};
  return f.dump();
}

// Reads watcher messages until one of `type` arrives (others are skipped); null on timeout.
json next_of_type(WsClient& ws, const std::string& type, int timeout_ms = 10000) {
  for (int i = 0; i < 1000; ++i) {
    const Result<std::string> m = ws.read(timeout_ms);
    if (!m) {
      ADD_FAILURE() << "no '" << type << "' message: " << m.error().message;
      return nullptr;
    }
    json j = json::parse(*m);
    if (j["type"] == type) return j;
  }
  return nullptr;
}

class HttpTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { server_ = std::make_unique<RunningServer>(GetParam()); }
  std::unique_ptr<RunningServer> server_;
};

TEST_P(HttpTest, StaticFilesNeedNoTokenAndStayInsideTheirFolders) {
  HttpClient http(server_->base_url());
  const HttpAnswer index = http.get("/");
  EXPECT_EQ(index.status, 200);
  EXPECT_EQ(index.header("content-type"), "text/html; charset=utf-8");
  EXPECT_NE(index.body.find("cathbox"), std::string::npos);
  if (std::filesystem::exists("/usr/share/javascript/three/build/three.module.js")) {
    const HttpAnswer three = http.get("/lib/three/build/three.module.js");
    EXPECT_EQ(three.status, 200);
    EXPECT_EQ(three.header("content-type"), "text/javascript; charset=utf-8");
  }
  for (const char* bad : {"/.secret", "/../../etc/passwd", "/%2e%2e/%2e%2e/etc/passwd", "/lib/three/../../../etc/passwd", "/a%00b",
                          "/lib/chart.js/%2e%2e/%2e%2e/passwd"}) {
    const HttpAnswer a = http.get(bad);
    EXPECT_TRUE(a.status == 404 || a.status == 400) << bad << " -> " << a.status;
    EXPECT_EQ(a.body.find("root:"), std::string::npos);
  }
  EXPECT_EQ(http.request("POST", "/index.html").status, 405);
}

TEST_P(HttpTest, EveryApiEndpointButLoginNeedsAToken) {
  HttpClient http(server_->base_url());
  for (const auto& [method, target] : std::vector<std::pair<std::string, std::string>>{
           {"GET", "/api/v1/me"}, {"POST", "/api/v1/logout"}, {"POST", "/api/v1/me/password"}, {"GET", "/api/v1/users"},
           {"POST", "/api/v1/users"}, {"PATCH", "/api/v1/users/x"}, {"GET", "/api/v1/cases"}, {"POST", "/api/v1/cases"},
           {"GET", "/api/v1/cases/x"}, {"GET", "/api/v1/cases/x/versions/1"}, {"GET", "/api/v1/cases/x/versions/1/bundle"},
           {"GET", "/api/v1/assignments"}, {"POST", "/api/v1/assignments"}, {"GET", "/api/v1/assignments/1"},
           {"DELETE", "/api/v1/assignments/1"}, {"GET", "/api/v1/results"}, {"POST", "/api/v1/results"}, {"GET", "/api/v1/results/1"},
           {"GET", "/api/v1/results/1/record"}, {"GET", "/api/v1/metrics"}, {"GET", "/api/v1/live/rigs"}}) {
    const HttpAnswer a = http.request(method, target, "{}");
    EXPECT_EQ(a.status, 401) << method << " " << target;
    EXPECT_EQ(a.header("www-authenticate"), "Bearer");
  }
  WsClient ws(5000);
  const Status refused = ws.connect(server_->base_url(), "/api/v1/live/watch", "");
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().status, 401);
  const Status forged = ws.connect(server_->base_url(), "/api/v1/live/rigs/r1/stream?case=x", "forged-token");
  ASSERT_FALSE(forged);
  EXPECT_EQ(forged.error().status, 401);
  // The upgrade's 401 names the scheme like every other 401 (RFC 9110 section 15.5.2).
  const std::string upgrade =
      "GET /api/v1/live/watch HTTP/1.1\r\nHost: x\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
      "Sec-WebSocket-Key: dGhlIHNhbXBsZSBub25jZQ==\r\nSec-WebSocket-Version: 13\r\n\r\n";
  const std::string answer = raw_exchange(server_->port(), upgrade);
  EXPECT_EQ(answer.rfind("HTTP/1.1 401", 0), 0U) << answer;
  EXPECT_NE(answer.find("WWW-Authenticate: Bearer\r\n"), std::string::npos) << answer;
}

TEST_P(HttpTest, OversizedHeadersAndBodiesAreRefusedBeforeTheyAreRead) {
  const std::string big_header = "GET /api/v1/me HTTP/1.1\r\nHost: x\r\nX-Big: " + std::string(20000, 'a') + "\r\n\r\n";
  EXPECT_EQ(raw_exchange(server_->port(), big_header).rfind("HTTP/1.1 431", 0), 0U);
  // A declared 10 MB JSON body: refused on the header, without waiting for the bytes.
  const std::string announced = "POST /api/v1/login HTTP/1.1\r\nHost: x\r\nContent-Length: 10000000\r\n\r\n{";
  const std::string answer = raw_exchange(server_->port(), announced);
  EXPECT_EQ(answer.rfind("HTTP/1.1 413", 0), 0U) << answer;
  EXPECT_NE(answer.find("over the limit of 65536 for POST /api/v1/login"), std::string::npos) << answer;
  // Chunked, without a length: counted while reading.
  std::string chunked = "POST /api/v1/login HTTP/1.1\r\nHost: x\r\nTransfer-Encoding: chunked\r\n\r\n";
  for (int i = 0; i < 20; ++i) chunked += "1000\r\n" + std::string(4096, 'x') + "\r\n";
  chunked += "0\r\n\r\n";
  EXPECT_EQ(raw_exchange(server_->port(), chunked).rfind("HTTP/1.1 413", 0), 0U);
}

TEST_P(HttpTest, MalformedRequestsAreA400AndTheServerCarriesOn) {
  for (const std::string& garbage : {std::string("GARBAGE\r\n\r\n"), std::string("GET / HTTP/9.9\r\n\r\n"),
                                     std::string("GET /api/v1/me HTTP/1.1\r\nHost x\r\n\r\n"), std::string("\x16\x03\x01\x02\x00\x01\x00", 7),
                                     std::string("POST /api/v1/login HTTP/1.1\r\nContent-Length: -5\r\n\r\n")}) {
    const std::string answer = raw_exchange(server_->port(), garbage, 2000);
    EXPECT_TRUE(answer.empty() || answer.rfind("HTTP/1.1 400", 0) == 0) << answer;
  }
  HttpClient http(server_->base_url());
  EXPECT_EQ(http.post_json("/api/v1/login", "{").status, 400);
  EXPECT_EQ(http.post_json("/api/v1/login", R"({"name":"x","password":"y"})").status, 401);
}

TEST_P(HttpTest, OneConnectionCarriesManyRequests) {
  const std::string token = server_->token_for("alice", Role::kTrainee);
  HttpClient http(server_->base_url());
  http.set_token(token);
  for (int i = 0; i < 20; ++i) EXPECT_EQ(http.get("/api/v1/me").status, 200);
  EXPECT_LE(server_->app->http().stats().connections, 3U);  // the login's, and this one
}

// A heavy answer (a debrief trace replaying a long record) that takes longer than the idle
// timeout still arrives whole: the write gets its own deadline.
TEST_P(HttpTest, ASlowHeavyAnswerArrivesWhole) {
  server_.reset();
  test::ServerOptions o;
  o.idle_timeout_s = 1;
  server_ = std::make_unique<RunningServer>(GetParam(), o);
  HttpClient http(server_->base_url());
  http.set_token(server_->token_for("alice", Role::kTrainee));
  json record = json::parse(test::FakeRecords::make("y_bifurcation", {{"tip_path_mm", 10}}));
  record["trace_delay_ms"] = 2500;
  const HttpAnswer up = http.request("POST", "/api/v1/results", record.dump(), {{"Content-Type", "application/octet-stream"}});
  ASSERT_EQ(up.status, 201) << up.body;
  const HttpAnswer trace = http.get("/api/v1/results/" + std::to_string(json::parse(up.body)["id"].get<int>()) + "/trace");
  ASSERT_EQ(trace.status, 200) << trace.problem();
  const json t = json::parse(trace.body);
  EXPECT_EQ(t["trace"]["pad"].get<std::string>().size(), 32U * 1024U * 1024U);
  EXPECT_EQ(trace.header("x-cathbox-trace").rfind("replayed; ", 0), 0U);
}

TEST_P(HttpTest, ApiAnswersAreNotCachedButCaseBundlesAreRevalidatedByTheirEtag) {
  HttpClient http(server_->base_url());
  http.set_token(server_->token_for("teacher", Role::kInstructor));
  const nlohmann::json body = {{"name", "ybif"}, {"case_file", "y_bifurcation.case"},
                               {"case", test::source_file("cases/y_bifurcation.case")}, {"hclm_file", "y_bifurcation.hclm"},
                               {"hclm", test::source_file("cases/y_bifurcation.hclm")}};
  ASSERT_EQ(http.post_json("/api/v1/cases", body.dump()).status, 201);
  EXPECT_EQ(http.get("/api/v1/cases").header("cache-control"), "no-store");
  const HttpAnswer bundle = http.get("/api/v1/cases/ybif/versions/1/bundle");
  ASSERT_EQ(bundle.status, 200);
  EXPECT_EQ(bundle.header("cache-control"), "private, no-cache");
  const std::string etag = bundle.header("etag");
  ASSERT_FALSE(etag.empty());
  const HttpAnswer again = http.request("GET", "/api/v1/cases/ybif/versions/1/bundle", {}, {{"If-None-Match", etag}});
  EXPECT_EQ(again.status, 304);
  EXPECT_TRUE(again.body.empty());
  // The browser's mesh too.
  const HttpAnswer mesh = http.get("/api/v1/cases/ybif/versions/1/mesh");
  ASSERT_EQ(mesh.status, 200);
  EXPECT_EQ(mesh.header("cache-control"), "private, no-cache");
  ASSERT_FALSE(mesh.header("etag").empty());
  EXPECT_NE(mesh.header("etag"), etag);
  const HttpAnswer mesh_again = http.request("GET", "/api/v1/cases/ybif/versions/1/mesh", {}, {{"If-None-Match", mesh.header("etag")}});
  EXPECT_EQ(mesh_again.status, 304);
  EXPECT_TRUE(mesh_again.body.empty());
}

TEST_P(HttpTest, FramesFromARigReachItsWatchers) {
  const std::string teacher = server_->token_for("teacher", Role::kInstructor);
  const std::string alice = server_->token_for("alice", Role::kTrainee);
  WsClient watcher;
  ASSERT_TRUE(watcher.connect(server_->base_url(), "/api/v1/live/watch?rigs=rig-1", teacher));
  EXPECT_EQ(next_of_type(watcher, "rigs")["rigs"].size(), 0U);
  LiveStream stream({server_->base_url(), alice, "rig-1", "ybif", 0, std::nullopt, 100});
  stream.push(frame(1));
  const json started = next_of_type(watcher, "started");
  EXPECT_EQ(started["rig"]["user"], "alice");
  const json got = next_of_type(watcher, "frame");
  EXPECT_EQ(got["rig"], "rig-1");
  EXPECT_EQ(got["frame"]["seq"], 1);
  EXPECT_EQ(got["frame"]["tools"][0]["nodes_mm"].size(), 8U);
  stream.push(frame(2));
  EXPECT_EQ(next_of_type(watcher, "frame")["frame"]["seq"], 2);
  // The rig is listed while it streams.
  HttpClient http(server_->base_url());
  http.set_token(teacher);
  const json rigs = json::parse(http.get("/api/v1/live/rigs").body);
  ASSERT_EQ(rigs["rigs"].size(), 1U);
  EXPECT_EQ(rigs["rigs"][0]["case"], "ybif");
}

TEST_P(HttpTest, TraineesWatchOnlyTheirOwnRig) {
  const std::string alice = server_->token_for("alice", Role::kTrainee);
  const std::string bob = server_->token_for("bob", Role::kTrainee);
  WsClient publisher;
  ASSERT_TRUE(publisher.connect(server_->base_url(), "/api/v1/live/rigs/rig-a/stream?case=ybif", alice));
  WsClient spy;
  const Status refused = spy.connect(server_->base_url(), "/api/v1/live/watch?rigs=rig-a", bob);
  ASSERT_FALSE(refused);
  EXPECT_EQ(refused.error().status, 403);
  EXPECT_EQ(refused.error().message, "HTTP 403: rig 'rig-a': trainees may watch only their own rig");
  // Bob may not take over Alice's rig name while she streams.
  WsClient thief;
  const Status taken = thief.connect(server_->base_url(), "/api/v1/live/rigs/rig-a/stream?case=ybif", bob);
  ASSERT_FALSE(taken);
  EXPECT_EQ(taken.error().status, 409);
  // Alice may watch herself; Bob's rig list is empty.
  WsClient self;
  ASSERT_TRUE(self.connect(server_->base_url(), "/api/v1/live/watch?rigs=rig-a", alice));
  EXPECT_EQ(next_of_type(self, "rigs")["rigs"].size(), 1U);
  HttpClient http(server_->base_url());
  http.set_token(bob);
  EXPECT_EQ(json::parse(http.get("/api/v1/live/rigs").body)["rigs"].size(), 0U);
  // A watch message for someone else's rig is refused on the socket, which stays open.
  WsClient bobs;
  ASSERT_TRUE(bobs.connect(server_->base_url(), "/api/v1/live/watch", bob));
  (void)next_of_type(bobs, "rigs");
  ASSERT_TRUE(bobs.send(R"({"type":"watch","rigs":["rig-a"]})"));
  EXPECT_EQ(next_of_type(bobs, "error")["error"], "rig 'rig-a': trainees may watch only their own rig");
}

TEST_P(HttpTest, BadFramesAreAnsweredAndTheStreamGoesOn) {
  const std::string teacher = server_->token_for("teacher", Role::kInstructor);
  const std::string alice = server_->token_for("alice", Role::kTrainee);
  WsClient watcher;
  ASSERT_TRUE(watcher.connect(server_->base_url(), "/api/v1/live/watch?rigs=rig-1", teacher));
  WsClient publisher;
  ASSERT_TRUE(publisher.connect(server_->base_url(), "/api/v1/live/rigs/rig-1/stream?case=ybif", alice));
  ASSERT_TRUE(publisher.send("{not json"));
  const std::string line = next_of_type(publisher, "error")["error"].get<std::string>();
  EXPECT_EQ(line, "frame: invalid JSON at byte 2: syntax error while parsing object key - invalid literal; last read: '{no'; expected string literal");
  ASSERT_TRUE(publisher.send(R"({"type":"frame","seq":1,"t_ms":0,"tip_mm":[1,2]})"));
  EXPECT_EQ(next_of_type(publisher, "error")["error"], "frame: field 'tip_mm': expected [x, y, z]");
  ASSERT_TRUE(publisher.send(frame(7)));
  EXPECT_EQ(next_of_type(watcher, "frame")["frame"]["seq"], 7);
  // A message over the size limit closes that socket (only).
  ASSERT_TRUE(publisher.send(std::string(kMaxFrameBytes + 100, ' ')));
  EXPECT_FALSE(publisher.read(5000).ok());
  ASSERT_TRUE(publisher.connect(server_->base_url(), "/api/v1/live/rigs/rig-1/stream?case=ybif", alice));
  ASSERT_TRUE(publisher.send(frame(8)));
  EXPECT_EQ(next_of_type(watcher, "frame")["frame"]["seq"], 8);
}

INSTANTIATE_TEST_SUITE_P(Backends, HttpTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
