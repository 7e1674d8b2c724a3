// Fuzzes the record-to-result path end to end: POST /api/v1/results (bytes cut at the route's
// body limit, kMaxRecordBytes, as the HTTP layer would) -> the session-replay record checker ->
// the library match, the completeness rule and the store, as a trainee with an assignment (odd
// second byte) or without. The first byte's low bit sets the record's version to this build's
// and corrects its CRCs first (see tests/fuzz/session/record_crc_fix.hpp). Property: nothing a
// trainee uploads gives a 5xx or a crash, and every refusal is one line.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>

#include "../session/record_crc_fix.hpp"
#include "server/server_app.hpp"

namespace {

using namespace cathbox::server;

struct World {
  std::unique_ptr<ServerCore> core;
  std::string trainee;
  std::string assignment;
};

World& world() {
  static World w = [] {
    World out;
    ServerConfig config;
    config.db_url = "sqlite::memory:";
    config.argon2 = test_argon2_params();
    Result<std::unique_ptr<ServerCore>> core = ServerCore::open(config);  // the session checker
    if (!core) {
      std::fprintf(stderr, "server core: %s\n", core.error().message.c_str());
      std::abort();
    }
    out.core = std::move(core.value());
    const auto require = [](bool ok, const std::string& what) {
      if (!ok) {
        std::fprintf(stderr, "%s\n", what.c_str());
        std::abort();
      }
    };
    require(static_cast<bool>(out.core->auth().create_user("teacher", Role::kInstructor, "password-123")), "create teacher");
    require(static_cast<bool>(out.core->auth().create_user("alice", Role::kTrainee, "password-123")), "create alice");
    const auto teacher = out.core->auth().login("teacher", "password-123", "fuzz");
    const auto alice = out.core->auth().login("alice", "password-123", "fuzz");
    require(teacher && alice, "login");
    out.trainee = alice.value().token;
    const auto call = [&](const std::string& method, const std::string& target, const std::string& body) {
      ApiRequest r;
      r.method = method;
      r.target = target;
      r.body = body;
      r.authorization = "Bearer " + teacher.value().token;
      r.remote_address = "fuzz";
      return out.core->api().handle(r);
    };
    // The bundled y-bifurcation as library case "y_bifurcation", assigned to alice.
    const std::string dir = std::string(CATHBOX_SOURCE_DIR) + "/cases/";
    const auto read = [](const std::string& path) {
      std::FILE* f = std::fopen(path.c_str(), "rb");
      std::string s;
      if (f == nullptr) return s;
      char buf[4096];
      for (std::size_t n; (n = std::fread(buf, 1, sizeof buf, f)) > 0;) s.append(buf, n);
      std::fclose(f);
      return s;
    };
    const nlohmann::json upload = {{"name", "y_bifurcation"}, {"case_file", "y_bifurcation.case"}, {"case", read(dir + "y_bifurcation.case")},
                                   {"hclm_file", "y_bifurcation.hclm"}, {"hclm", read(dir + "y_bifurcation.hclm")}};
    const ApiResponse made = call("POST", "/api/v1/cases", upload.dump());
    require(made.status == 201, "case upload: " + made.body);
    const ApiResponse a = call("POST", "/api/v1/assignments", R"({"trainee":"alice","case":"y_bifurcation"})");
    require(a.status == 201, "assignment: " + a.body);
    out.assignment = std::to_string(nlohmann::json::parse(a.body)["id"].get<int>());
    return out;
  }();
  return w;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 2) return 0;
  World& w = world();
  std::vector<uint8_t> bytes(data + 2, data + std::min(size, kMaxRecordBytes + 2));
  if ((data[0] & 1u) != 0u) fix_crcs(bytes);
  ApiRequest r;
  r.method = "POST";
  r.target = (data[1] & 1u) != 0u ? "/api/v1/results?assignment=" + w.assignment : "/api/v1/results";
  r.body.assign(bytes.begin(), bytes.end());
  r.authorization = "Bearer " + w.trainee;
  r.remote_address = "fuzz";
  const ApiResponse answer = w.core->api().handle(r);
  if (answer.status >= 500 || answer.status < 200) {
    std::fprintf(stderr, "status %d: %s\n", answer.status, answer.body.c_str());
    std::abort();
  }
  if (answer.status >= 400) {
    const nlohmann::json j = nlohmann::json::parse(answer.body, nullptr, false);
    if (!j.is_object() || !j.contains("error") || j["error"].get<std::string>().find('\n') != std::string::npos) std::abort();
  }
  return 0;
}
