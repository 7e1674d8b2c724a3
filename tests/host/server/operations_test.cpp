// What a centre's monitoring reads, over real sockets on SQLite and PostgreSQL: /healthz,
// /readyz (which follows the database), and /metrics in the Prometheus text format.
#include <gtest/gtest.h>

#include <regex>
#include <sstream>

#include <signal.h>

#include <nlohmann/json.hpp>

#include "server/log_line.hpp"
#include "server/server_metrics.hpp"
#include "server/testing/child_process.hpp"
#include "support/server_fixture.hpp"

namespace cathbox::server {
namespace {

using test::RunningServer;

class OperationsTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override { server_ = std::make_unique<RunningServer>(GetParam()); }
  std::unique_ptr<RunningServer> server_;
};

// Every line of a Prometheus text exposition (format 0.0.4): a comment, or NAME{LABELS} VALUE.
void expect_exposition_format(const std::string& text) {
  static const std::regex sample(R"(^[a-zA-Z_:][a-zA-Z0-9_:]*(\{([a-zA-Z_][a-zA-Z0-9_]*="[^"\\\n]*",?)*\})? (?:[-+0-9.eE]+|\+Inf|NaN)$)");
  std::istringstream lines(text);
  int samples = 0;
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("# HELP ", 0) == 0 || line.rfind("# TYPE ", 0) == 0) continue;
    EXPECT_TRUE(std::regex_match(line, sample)) << line;
    ++samples;
  }
  EXPECT_GT(samples, 20);
}

std::string metrics_of(const RunningServer& server) {
  HttpClient http(server.base_url());
  const HttpAnswer a = http.get("/metrics");
  EXPECT_EQ(a.status, 200) << a.problem();
  EXPECT_EQ(a.header("content-type"), "text/plain; version=0.0.4; charset=utf-8");
  return a.body;
}

TEST_P(OperationsTest, HealthAndReadinessFollowTheProcessAndItsDatabase) {
  HttpClient http(server_->base_url());
  EXPECT_EQ(http.get("/healthz").status, 200);
  EXPECT_EQ(http.get("/healthz").body, "ok\n");
  EXPECT_EQ(http.get("/readyz").body, "ready\n");
  EXPECT_EQ(http.request("POST", "/readyz").status, 405);
  if (GetParam() != "postgresql") return;
  test::stop_postgres("fast");
  const HttpAnswer down = http.get("/readyz");
  EXPECT_EQ(down.status, 503);
  EXPECT_EQ(down.body.rfind("not ready: database unavailable", 0), 0U) << down.body;
  EXPECT_EQ(http.get("/healthz").status, 200);  // alive, only not ready
  test::start_postgres();
  EXPECT_EQ(http.get("/readyz").status, 200);
}

TEST_P(OperationsTest, MetricsCountRequestsByRouteAndShowLiveWatchersAndThePool) {
  const std::string token = server_->token_for("ada", Role::kInstructor);
  HttpClient http(server_->base_url());
  EXPECT_EQ(http.get("/api/v1/me").status, 401);
  EXPECT_EQ(http.get("/api/v1/results/77").status, 401);
  EXPECT_EQ(http.get("/api/v1/results/78").status, 401);
  WsClient ws(5000);
  ASSERT_TRUE(ws.connect(server_->base_url(), "/api/v1/live/watch", token));
  ASSERT_TRUE(ws.read(5000));
  const std::string m = metrics_of(*server_);
  expect_exposition_format(m);
  EXPECT_NE(m.find("cathbox_http_requests_total{route=\"GET /api/v1/me\",status=\"401\"} 1\n"), std::string::npos) << m;
  EXPECT_NE(m.find("cathbox_http_requests_total{route=\"GET /api/v1/results/:id\",status=\"401\"} 2\n"), std::string::npos);
  EXPECT_NE(m.find("cathbox_http_requests_total{route=\"POST /api/v1/login\",status=\"200\"} 1\n"), std::string::npos);
  EXPECT_NE(m.find("cathbox_http_request_seconds_bucket{route=\"GET /api/v1/results/:id\",le=\"+Inf\"} 2\n"), std::string::npos);
  EXPECT_NE(m.find("cathbox_http_request_seconds_count{route=\"GET /api/v1/me\"} 1\n"), std::string::npos);
  EXPECT_NE(m.find("cathbox_live_watchers 1\n"), std::string::npos);
  EXPECT_NE(m.find("cathbox_live_rigs 0\n"), std::string::npos);
  EXPECT_NE(m.find("cathbox_db_pool_max 8\n"), std::string::npos);
  EXPECT_NE(m.find("cathbox_upload_queue 0\n"), std::string::npos);
  ws.close();
  // The watcher's end is seen at the next scrape.
  for (int i = 0; i < 200 && metrics_of(*server_).find("cathbox_live_watchers 0\n") == std::string::npos; ++i) {
    ASSERT_EQ(http.get("/healthz").status, 200);
  }
  EXPECT_NE(metrics_of(*server_).find("cathbox_live_watchers 0\n"), std::string::npos);
}

TEST(ServerMetricsTest, RoutesNameTheEndpointNotTheIdsAndHistogramsAreCumulative) {
  EXPECT_EQ(ServerMetrics::route_of("GET", "/api/v1/results/12/record?x=1"), "GET /api/v1/results/:id/record");
  EXPECT_EQ(ServerMetrics::route_of("GET", "/api/v1/cases/ybif/versions/3/bundle"), "GET /api/v1/cases/:id/versions/:id/bundle");
  EXPECT_EQ(ServerMetrics::route_of("GET", "/js/api.js"), "GET static");
  EXPECT_EQ(ServerMetrics::route_of("GET", "/api/v1/%22%7D%20evil"), "GET /api/v1/:id");
  EXPECT_EQ(ServerMetrics::route_of("BREW", "/api/v1/me"), "OTHER /api/v1/me");  // invented methods: one label
  ServerMetrics m;
  m.observe_request("GET /api/v1/me", 200, 0.002);
  m.observe_request("GET /api/v1/me", 200, 0.2);
  m.observe_upload_check(3.0);
  const std::string text = m.render(ScrapeGauges{});
  EXPECT_NE(text.find("cathbox_http_request_seconds_bucket{route=\"GET /api/v1/me\",le=\"0.001\"} 0\n"), std::string::npos) << text;
  EXPECT_NE(text.find("cathbox_http_request_seconds_bucket{route=\"GET /api/v1/me\",le=\"0.0025\"} 1\n"), std::string::npos);
  EXPECT_NE(text.find("cathbox_http_request_seconds_bucket{route=\"GET /api/v1/me\",le=\"0.25\"} 2\n"), std::string::npos);
  const std::string sum_key = "cathbox_http_request_seconds_sum{route=\"GET /api/v1/me\"} ";
  const std::size_t sum_at = text.find(sum_key);
  ASSERT_NE(sum_at, std::string::npos);
  EXPECT_DOUBLE_EQ(std::stod(text.substr(sum_at + sum_key.size())), 0.002 + 0.2);
  EXPECT_NE(text.find("cathbox_upload_check_seconds_bucket{le=\"2.5\"} 0\n"), std::string::npos);
  EXPECT_NE(text.find("cathbox_upload_check_seconds_bucket{le=\"5\"} 1\n"), std::string::npos);
  expect_exposition_format(text);
}

TEST(LogLineTest, TextForATerminalOrOneJsonObjectALine) {
  const std::int64_t t_us = 1'795'860'000'000'000;  // 2026-11-28T10:00:00Z
  EXPECT_EQ(log_line(LogFormat::kText, "info", "listening on http://127.0.0.1:8080", t_us), "cathbox-server: listening on http://127.0.0.1:8080");
  EXPECT_EQ(log_line(LogFormat::kText, "warning", "--insecure-http: ...", t_us), "cathbox-server: WARNING: --insecure-http: ...");
  const std::string line = log_line(LogFormat::kJson, "error", "--tls-key k.pem: \"bad\"\nsecond line \xff", t_us, {{"file", "k.pem"}});
  EXPECT_EQ(line.find('\n'), std::string::npos);  // one line, whatever the message holds
  const nlohmann::json j = nlohmann::json::parse(line);
  EXPECT_EQ(j["time"], "2026-11-28T10:00:00.000000Z");
  EXPECT_EQ(j["level"], "error");
  EXPECT_EQ(j["program"], "cathbox-server");
  EXPECT_EQ(j["msg"], "--tls-key k.pem: \"bad\"\nsecond line \xef\xbf\xbd");  // invalid UTF-8 replaced
  EXPECT_EQ(j["file"], "k.pem");
  EXPECT_EQ(line.rfind(R"({"time":)", 0), 0U);
  EXPECT_FALSE(parse_log_format("xml"));
}

// The program itself with --log-format json: its start, a certificate reload refused (plain
// HTTP has none) and its stop are JSON lines; a bad format is one line and exit 2.
TEST(LogLineTest, TheServerLogsJsonLinesWhenAsked) {
  using testing::ChildOptions;
  using testing::ChildProcess;
  const std::string program = testing::sibling_program("cathbox-server");
  ChildProcess server;
  ChildOptions o;
  o.capture_stdout = true;
  ASSERT_EQ(server.start({program, "--db", test::fresh_database_url("sqlite"), "--listen", "127.0.0.1:0", "--log-format", "json"}, o), "");
  const std::optional<std::string> first = server.read_line();
  ASSERT_TRUE(first);
  const nlohmann::json started = nlohmann::json::parse(*first);
  EXPECT_EQ(started["level"], "info");
  EXPECT_EQ(started["msg"].get<std::string>().rfind("listening on http://127.0.0.1:", 0), 0U) << *first;
  EXPECT_EQ(started["url"].get<std::string>().rfind("http://127.0.0.1:", 0), 0U);
  EXPECT_FALSE(started["schema"].get<std::string>().empty());
  server.signal(SIGHUP);
  const nlohmann::json reload = nlohmann::json::parse(server.read_line().value_or("{}"));
  EXPECT_EQ(reload["level"], "warning");
  EXPECT_EQ(reload["msg"], "SIGHUP: TLS reload: this server speaks plain HTTP (no --tls-cert) (the old certificate stays)");
  server.signal(SIGTERM);
  const nlohmann::json stop = nlohmann::json::parse(server.read_line().value_or("{}"));
  EXPECT_EQ(stop["msg"], "stopping (signal 15)");
  EXPECT_EQ(server.wait(), 0);

  ChildProcess bad;
  ASSERT_EQ(bad.start({program, "--db", test::fresh_database_url("sqlite"), "--log-format", "xml"}, ChildOptions{}), "");
  EXPECT_EQ(bad.wait(), 2);
}

INSTANTIATE_TEST_SUITE_P(Backends, OperationsTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

}  // namespace
}  // namespace cathbox::server
