// Several cathbox-server instances on one real PostgreSQL: live streams fan out through
// LISTEN/NOTIFY (a rig streams to A, an instructor watches on B), large frames go through the
// overflow table, and a PostgreSQL restart is survived by the bus and the API.
#include <gtest/gtest.h>

#include <thread>

#include "support/server_fixture.hpp"

namespace cathbox::server {
namespace {

using json = nlohmann::json;
using test::RunningServer;

std::string frame(int seq, std::size_t nodes = 8) {
  json pts = json::array();
  for (std::size_t i = 0; i < nodes; ++i) pts.push_back({0.123456 * static_cast<double>(i), 1.25, -3.0});
  return json{{"type", "frame"}, {"seq", seq}, {"t_ms", seq * 33.3}, {"tools", json::array({{{"name", "guidewire"}, {"nodes_mm", pts}}})}}.dump();
}

// Pushes frames (seq from `from`) until the watcher receives a frame with seq >= from, reading
// with short timeouts in between; the received frame, or null after `attempts`.
json feed_until_received(LiveStream& stream, WsClient& watcher, int from, int attempts = 120) {
  int seq = from;
  for (int i = 0; i < attempts; ++i) {
    stream.push(frame(seq++));
    for (;;) {
      const Result<std::string> m = watcher.read(250);
      if (!m) {
        if (m.error().message != WsClient::kReadTimeout) {
          ADD_FAILURE() << "watcher: " << m.error().message;
          return nullptr;
        }
        break;
      }
      json j = json::parse(*m);
      if (j["type"] == "frame" && j["frame"]["seq"].get<int>() >= from) return j;
    }
  }
  ADD_FAILURE() << "no frame from seq " << from << " after " << attempts << " attempts";
  return nullptr;
}

class TwoInstances : public ::testing::Test {
 protected:
  void SetUp() override {
    const std::string url = test::fresh_database_url("postgresql");
    a_ = std::make_unique<RunningServer>("postgresql", test::ServerOptions{"", url, "instance-a"});
    b_ = std::make_unique<RunningServer>("postgresql", test::ServerOptions{"", url, "instance-b"});
    teacher_ = b_->token_for("teacher", Role::kInstructor);
    alice_ = a_->token_for("alice", Role::kTrainee);
  }
  std::unique_ptr<RunningServer> a_, b_;
  std::string teacher_, alice_;
};

TEST_F(TwoInstances, ARigStreamingToOneInstanceIsWatchedFromTheOther) {
  WsClient watcher;
  ASSERT_TRUE(watcher.connect(b_->base_url(), "/api/v1/live/watch?rigs=rig-1", teacher_));
  LiveStream stream({a_->base_url(), alice_, "rig-1", "neuro", 2, std::nullopt, 100});
  const json got = feed_until_received(stream, watcher, 1);
  ASSERT_FALSE(got.is_null());
  EXPECT_EQ(got["rig"], "rig-1");
  // B lists the rig, streaming on A.
  HttpClient http(b_->base_url());
  http.set_token(teacher_);
  const json rigs = json::parse(http.get("/api/v1/live/rigs").body);
  ASSERT_EQ(rigs["rigs"].size(), 1U);
  EXPECT_EQ(rigs["rigs"][0]["instance"], "instance-a");
  EXPECT_EQ(rigs["rigs"][0]["case_version"], 2);
  // A frame far over NOTIFY's 8000-byte payload travels through the overflow table.
  const std::string big = frame(100000, 900);
  ASSERT_GT(big.size(), 20000U);
  json large;
  for (int i = 0; i < 40 && large.is_null(); ++i) {
    stream.push(big);
    for (;;) {
      const Result<std::string> m = watcher.read(250);
      if (!m) break;
      json j = json::parse(*m);
      if (j["type"] == "frame" && j["frame"]["seq"] == 100000) {
        large = j;
        break;
      }
    }
  }
  ASSERT_FALSE(large.is_null());
  EXPECT_EQ(large["frame"]["tools"][0]["nodes_mm"].size(), 900U);
  EXPECT_GE(a_->app->pg_bus()->stats().overflowed, 1U);
  EXPECT_GE(b_->app->pg_bus()->stats().received, 2U);
}

TEST_F(TwoInstances, TheBusAndTheApiComeBackAfterPostgresRestarts) {
  WsClient watcher;
  ASSERT_TRUE(watcher.connect(b_->base_url(), "/api/v1/live/watch?rigs=rig-2", teacher_));
  LiveStream stream({a_->base_url(), alice_, "rig-2", "neuro", 0, std::nullopt, 100});
  ASSERT_FALSE(feed_until_received(stream, watcher, 1).is_null());

  test::stop_postgres("fast");
  // While the database is down the API answers 503 (retry), never 500.
  HttpClient http(a_->base_url());
  http.set_token(alice_);
  const HttpAnswer down = http.get("/api/v1/me");
  EXPECT_EQ(down.status, 503) << down.body;
  EXPECT_EQ(down.header("retry-after"), "1");
  test::start_postgres();

  EXPECT_EQ(http.get("/api/v1/me").status, 200);
  // Frames flow again from A to B once both sides have reconnected.
  ASSERT_FALSE(feed_until_received(stream, watcher, 1000).is_null());
  EXPECT_GE(b_->app->pg_bus()->stats().reconnects, 1U);
}

}  // namespace
}  // namespace cathbox::server
