#pragma once
// The whole API over one backend without sockets: store, virtual clock, auth (light Argon2
// parameters), case library, live hub and service, and a record checker (FakeRecords until the
// session-replay checker replaces it in the tests that need real records).
#include <functional>
#include <map>
#include <memory>
#include <string>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "server/api.hpp"
#include "server/live_hub.hpp"
#include "server/server_app.hpp"
#include "server/record_checker.hpp"
#include "support/backends.hpp"

namespace cathbox::server::test {

// A record checker for API tests of routing, roles and idempotency: a "record" is JSON
// {"case_file", "case", "hclm_file", "hclm", "metrics": {...}, "tampered": bool}.
class FakeRecords final : public RecordChecker {
 public:
  Result<CheckedRecord> check(std::string_view bytes) override;
  // {"format": "fake-trace", "pad": 32 MB}, after the record's "trace_delay_ms" (a slow replay).
  Result<std::string> trace(std::string_view bytes) override;
  std::vector<std::string> metric_names() const override;
  static std::string make(const std::string& case_stem, const std::map<std::string, double>& metrics, bool tampered = false,
                          const std::string& salt = "");
};

// Reads a file of the source tree (cases/..., tests/...).
[[nodiscard]] std::string source_file(const std::string& relative);
// A file's bytes ("" when it cannot be read).
[[nodiscard]] std::string file_bytes(const std::string& path);

class ApiFixture {
 public:
  // `db_url`: an existing database of the backend instead of a fresh one; `configure`: more
  // settings (a cache folder, the record retention) before the core opens.
  explicit ApiFixture(const std::string& backend, std::unique_ptr<RecordChecker> checker = std::make_unique<FakeRecords>(),
                      const std::string& db_url = "", const std::function<void(ServerConfig&)>& configure = {});
  ~ApiFixture();

  ApiResponse call(const std::string& method, const std::string& target, const std::string& body = "", const std::string& token = "",
                   const std::string& address = "10.0.0.1");
  nlohmann::json call_json(const std::string& method, const std::string& target, const nlohmann::json& body, const std::string& token,
                           int expected_status);
  // Creates the user directly and logs in; answers the token.
  std::string user(const std::string& name, Role role, const std::string& password = "password-123");
  std::string login(const std::string& name, const std::string& password = "password-123");
  // Uploads cases/<stem>.case (and its HCLM) under `name` as `token`.
  ApiResponse upload_bundled_case(const std::string& stem, const std::string& name, const std::string& token);

  ManualClock clock;
  std::string db_url;
  std::unique_ptr<ServerCore> core;
  Store* store = nullptr;
  Auth* auth = nullptr;
  Api* api = nullptr;
};

// A training centre on one backend (the test's parameter) with an admin (root), an instructor
// (teacher) and two trainees (alice, bob), logged in.
class CentreTest : public ::testing::TestWithParam<std::string> {
 protected:
  void SetUp() override {
    f_ = std::make_unique<ApiFixture>(GetParam());
    admin_ = f_->user("root", Role::kAdmin);
    teacher_ = f_->user("teacher", Role::kInstructor);
    alice_ = f_->user("alice", Role::kTrainee);
    bob_ = f_->user("bob", Role::kTrainee);
  }
  std::unique_ptr<ApiFixture> f_;
  std::string admin_, teacher_, alice_, bob_;
};

// {"error": ...} of a response, or "" when it has none.
[[nodiscard]] std::string error_of(const ApiResponse& r);

}  // namespace cathbox::server::test
