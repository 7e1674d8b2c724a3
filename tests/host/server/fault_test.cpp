// Faults with the real program: cathbox-server killed with SIGKILL in the middle of uploads,
// and PostgreSQL restarted under load. Clients keep what was not acknowledged and retry it;
// afterwards every acknowledged upload is present, everything is stored exactly once, and no
// request was answered with a 5xx other than 503 (database away, retry).
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <condition_variable>
#include <mutex>
#include <set>
#include <thread>

#include "server/auth.hpp"
#include "server/migrations.hpp"
#include "server/sha256.hpp"
#include "support/server_fixture.hpp"
#include "server/testing/server_process.hpp"

namespace cathbox::server {
namespace {

using json = nlohmann::json;

constexpr int kClients = 4;
constexpr int kUploadsPerClient = 6;

// One upload a client wants acknowledged: a case under a name of its own.
struct Upload {
  std::string name;
  std::string body;
  std::string hash;  // the case's content hash, as the server reports it
};

std::vector<Upload> make_uploads(int client) {
  const std::string base = test::source_file("cases/y_bifurcation.case");
  const std::string hclm = test::source_file("cases/y_bifurcation.hclm");
  std::vector<Upload> out;
  for (int i = 0; i < kUploadsPerClient; ++i) {
    Upload u;
    u.name = "c" + std::to_string(client) + "-" + std::to_string(i);
    const std::string text = base + "\n# variant " + u.name + "\n";
    u.body = json{{"name", u.name}, {"case_file", "y.case"}, {"case", text}, {"hclm_file", "y_bifurcation.hclm"}, {"hclm", hclm}}.dump();
    out.push_back(std::move(u));
  }
  return out;
}

// The clients' side: uploads until each is acknowledged; after a failure, waits for the next
// "the server is back" generation instead of sleeping.
class Clients {
 public:
  explicit Clients(std::string base_url, std::string token) : base_url_(std::move(base_url)), token_(std::move(token)) {}

  void run() {
    for (int c = 0; c < kClients; ++c) threads_.emplace_back([this, c] { client(c); });
  }
  void join() {
    for (auto& t : threads_) t.join();
  }
  // Blocks until at least n uploads were acknowledged.
  void wait_acknowledged(int n) {
    std::unique_lock lock(mutex_);
    changed_.wait(lock, [&] { return static_cast<int>(acknowledged_.size()) >= n; });
  }
  void server_back() {
    {
      std::lock_guard lock(mutex_);
      ++generation_;
    }
    changed_.notify_all();
  }
  std::map<std::string, std::string> acknowledged() {
    std::lock_guard lock(mutex_);
    return acknowledged_;
  }
  std::vector<std::string> bad_answers() {
    std::lock_guard lock(mutex_);
    return bad_;
  }
  int failures() const { return failures_.load(); }

 private:
  void client(int c) {
    HttpClient http(base_url_, 20000);
    http.set_token(token_);
    for (const Upload& u : make_uploads(c)) {
      for (int attempt = 0;; ++attempt) {
        int seen_generation = 0;
        {
          std::lock_guard lock(mutex_);
          seen_generation = generation_;
        }
        const HttpAnswer a = http.post_json("/api/v1/cases", u.body);
        if (a.status == 200 || a.status == 201) {
          std::lock_guard lock(mutex_);
          acknowledged_[u.name] = json::parse(a.body)["content_hash"].get<std::string>();
          changed_.notify_all();
          break;
        }
        ++failures_;
        if (a.status != 0 && a.status != 503) {
          std::lock_guard lock(mutex_);
          bad_.push_back(u.name + ": " + std::to_string(a.status) + " " + a.problem());
          break;
        }
        if (attempt > 50) {
          std::lock_guard lock(mutex_);
          bad_.push_back(u.name + ": gave up: " + a.problem());
          break;
        }
        // Unreachable or 503: try again once the server (or its database) is back.
        std::unique_lock lock(mutex_);
        changed_.wait(lock, [&] { return generation_ != seen_generation; });
      }
    }
  }

  std::string base_url_;
  std::string token_;
  std::vector<std::thread> threads_;
  std::mutex mutex_;
  std::condition_variable changed_;
  int generation_ = 0;
  std::map<std::string, std::string> acknowledged_;
  std::vector<std::string> bad_;
  std::atomic<int> failures_{0};
};

std::string make_instructor(const std::string& db_url, const std::string& base_url) {
  DatabaseOpen opened = open_database(db_url);
  if (!opened.db) throw std::runtime_error(opened.error);
  Store store(std::move(opened.db));
  SystemClock clock;
  Auth auth(store, clock, PasswordHasher(test_argon2_params()));
  (void)auth.create_user("teacher", Role::kInstructor, "password-123");
  ServerClient client(base_url);
  if (!client.login("teacher", "password-123")) throw std::runtime_error("login failed");
  return client.token();
}

// Every acknowledged upload is in the library with the acknowledged content, and every upload
// was stored exactly once (one version each).
void expect_all_stored_once(const std::string& db_url, const std::map<std::string, std::string>& acknowledged) {
  DatabaseOpen opened = open_database(db_url);
  ASSERT_TRUE(opened.db) << opened.error;
  Store store(std::move(opened.db));
  EXPECT_EQ(acknowledged.size(), static_cast<std::size_t>(kClients * kUploadsPerClient));
  for (const auto& [name, hash] : acknowledged) {
    const std::vector<CaseVersion> versions = store.case_versions(name);
    ASSERT_EQ(versions.size(), 1U) << name;
    EXPECT_EQ(versions[0].content_hash, hash) << name;
  }
  EXPECT_EQ(store.list_cases().size(), static_cast<std::size_t>(kClients * kUploadsPerClient));
}

class FaultTest : public ::testing::TestWithParam<std::string> {};

TEST_P(FaultTest, AcknowledgedUploadsSurviveSigkillAndTheRestAreRetried) {
  const std::string url = test::fresh_database_url(GetParam());
  {
    // Migrate before the first server starts, so the instructor can be created beside it.
    DatabaseOpen opened = open_database(url);
    ASSERT_TRUE(opened.db) << opened.error;
    ASSERT_TRUE(migrate(*opened.db));
  }
  testing::ServerProcess server(url);
  Clients clients(server.base_url(), make_instructor(url, server.base_url()));
  clients.run();
  clients.wait_acknowledged(kClients * kUploadsPerClient / 3);
  server.kill(SIGKILL);
  const auto before_restart = clients.acknowledged();
  server.restart();
  clients.server_back();
  clients.join();
  EXPECT_TRUE(clients.bad_answers().empty()) << clients.bad_answers().front();
  // The kill fell in the middle: some uploads came after it, and some attempts failed.
  EXPECT_LT(before_restart.size(), static_cast<std::size_t>(kClients * kUploadsPerClient));
  EXPECT_GE(clients.failures(), 1);
  std::printf("SIGKILL (%s): %zu uploads acknowledged before the kill, %d attempts failed and were retried\n", GetParam().c_str(),
              before_restart.size(), clients.failures());
  // Everything acknowledged before the kill is there with the same content.
  DatabaseOpen opened = open_database(url);
  ASSERT_TRUE(opened.db);
  Store store(std::move(opened.db));
  for (const auto& [name, hash] : before_restart) {
    const auto v = store.case_version(name, 0);
    ASSERT_TRUE(v) << name << " was acknowledged before the kill but is gone";
    EXPECT_EQ(v->content_hash, hash);
  }
  expect_all_stored_once(url, clients.acknowledged());
  EXPECT_TRUE(server.alive());
}

INSTANTIATE_TEST_SUITE_P(Backends, FaultTest, ::testing::ValuesIn(test::kBackends), test::BackendName());

class PostgresFault : public ::testing::TestWithParam<std::string> {};

TEST_P(PostgresFault, RestartUnderLoadLosesNothingAcknowledged) {
  const std::string url = test::fresh_database_url(GetParam());
  testing::ServerProcess server(url);
  Clients clients(server.base_url(), make_instructor(url, server.base_url()));
  clients.run();
  clients.wait_acknowledged(kClients * kUploadsPerClient / 3);
  const std::size_t before = clients.acknowledged().size();
  test::stop_postgres("fast");
  test::start_postgres();
  clients.server_back();
  clients.join();
  EXPECT_TRUE(clients.bad_answers().empty()) << clients.bad_answers().front();
  EXPECT_LT(before, static_cast<std::size_t>(kClients * kUploadsPerClient));
  std::printf("PostgreSQL restart: %zu uploads acknowledged before, %d attempts failed (503 or cut off) and were retried\n", before,
              clients.failures());
  expect_all_stored_once(url, clients.acknowledged());
  EXPECT_TRUE(server.alive()) << "cathbox-server died when PostgreSQL restarted";
}

INSTANTIATE_TEST_SUITE_P(Backends, PostgresFault, ::testing::Values("postgresql"), test::BackendName());

}  // namespace
}  // namespace cathbox::server
