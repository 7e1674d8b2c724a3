#include "support/api_fixture.hpp"

#include <chrono>
#include <fstream>
#include <sstream>
#include <thread>

#include "server/json_input.hpp"
#include "server/sha256.hpp"
#include "scenario/case_file.hpp"

namespace cathbox::server::test {

std::string source_file(const std::string& relative) {
  std::ifstream in(std::string(CATHBOX_SOURCE_DIR) + "/" + relative, std::ios::binary);
  if (!in) throw std::runtime_error("missing source file " + relative);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

Result<std::string> FakeRecords::trace(std::string_view bytes) {
  Result<nlohmann::json> j = parse_json_object(bytes, "record");
  if (!j) return make_error(422, "record: byte 0: not a record");
  std::this_thread::sleep_for(std::chrono::milliseconds(j.value().value("trace_delay_ms", 0)));
  return nlohmann::json{{"format", "fake-trace"}, {"pad", std::string(32 * 1024 * 1024, 'x')}}.dump();
}

Result<CheckedRecord> FakeRecords::check(std::string_view bytes) {
  Result<nlohmann::json> j = parse_json_object(bytes, "record");
  if (!j) return make_error(422, "record: byte 0: not a record");
  if (j.value().value("tampered", false)) return make_error(422, "record: tick 1200: state hash differs (tampered or broken)");
  CheckedRecord r;
  r.case_files.case_file = j.value().at("case_file").get<std::string>();
  r.case_files.case_text = j.value().at("case").get<std::string>();
  r.case_files.hclm_file = j.value().at("hclm_file").get<std::string>();
  r.case_files.hclm_text = j.value().at("hclm").get<std::string>();
  r.started_us = 1'700'000'000'000'000;
  r.duration_ms = 90'000;
  r.complete = !j.value().value("cut", false);
  // The run: the object as parsed (key order and spacing do not count), without its "note" (an
  // informational field).
  nlohmann::json run = j.value();
  run.erase("note");
  r.run_hash = sha256_hex(run.dump());
  for (const auto& [k, v] : j.value().at("metrics").items()) r.metrics.push_back(MetricValue{k, v.get<double>()});
  return r;
}

std::vector<std::string> FakeRecords::metric_names() const {
  return {"target_reached", "procedure_time_s", "fluoroscopy_time_s", "peak_wall_force_mN", "wall_contacts"};
}

std::string FakeRecords::make(const std::string& case_stem, const std::map<std::string, double>& metrics, bool tampered,
                              const std::string& salt) {
  const std::string case_text = source_file("cases/" + case_stem + ".case");
  const tool::CaseParse parsed = tool::parse_case(case_text, case_stem + ".case");
  const std::string hclm = parsed && !parsed->vessel_path.empty() ? parsed->vessel_path : "";
  nlohmann::json j = {{"case_file", case_stem + ".case"},
                      {"case", case_text},
                      {"hclm_file", hclm},
                      {"hclm", hclm.empty() ? "" : source_file("cases/" + hclm)},
                      {"metrics", metrics},
                      {"tampered", tampered},
                      {"salt", salt}};
  return j.dump();
}

ApiFixture::ApiFixture(const std::string& backend, std::unique_ptr<RecordChecker> record_checker, const std::string& url,
                       const std::function<void(ServerConfig&)>& configure)
    : db_url(url.empty() ? fresh_database_url(backend) : url) {
  ServerConfig config;
  config.db_url = db_url;
  config.argon2 = test_argon2_params();
  config.clock = &clock;
  config.instance = "test-instance";
  config.checker = std::move(record_checker);
  if (configure) configure(config);
  Result<std::unique_ptr<ServerCore>> opened = ServerCore::open(config);
  if (!opened) throw std::runtime_error(opened.error().message);
  core = std::move(opened.value());
  store = &core->store();
  auth = &core->auth();
  api = &core->api();
}

ApiFixture::~ApiFixture() = default;

ApiResponse ApiFixture::call(const std::string& method, const std::string& target, const std::string& body, const std::string& token,
                             const std::string& address) {
  ApiRequest r;
  r.method = method;
  r.target = target;
  r.body = body;
  r.authorization = token.empty() ? "" : "Bearer " + token;
  r.remote_address = address;
  return api->handle(r);
}

nlohmann::json ApiFixture::call_json(const std::string& method, const std::string& target, const nlohmann::json& body,
                                     const std::string& token, int expected_status) {
  const ApiResponse r = call(method, target, body.is_null() ? "" : body.dump(), token);
  EXPECT_EQ(r.status, expected_status) << method << " " << target << ": " << r.body;
  if (r.body.empty()) return nullptr;
  return nlohmann::json::parse(r.body);
}

std::string ApiFixture::user(const std::string& name, Role role, const std::string& password) {
  const Result<User> made = auth->create_user(name, role, password);
  EXPECT_TRUE(made) << (made ? "" : made.error().message);
  return login(name, password);
}

std::string ApiFixture::login(const std::string& name, const std::string& password) {
  const ApiResponse r = call("POST", "/api/v1/login", nlohmann::json{{"name", name}, {"password", password}}.dump());
  EXPECT_EQ(r.status, 200) << r.body;
  if (r.status != 200) return "";
  return nlohmann::json::parse(r.body).at("token").get<std::string>();
}

ApiResponse ApiFixture::upload_bundled_case(const std::string& stem, const std::string& name, const std::string& token) {
  const std::string case_text = source_file("cases/" + stem + ".case");
  const tool::CaseParse parsed = tool::parse_case(case_text, stem + ".case");
  nlohmann::json body = {{"name", name}, {"case_file", stem + ".case"}, {"case", case_text}};
  if (parsed && !parsed->vessel_path.empty()) {
    body["hclm_file"] = parsed->vessel_path;
    body["hclm"] = source_file("cases/" + parsed->vessel_path);
  }
  return call("POST", "/api/v1/cases", body.dump(), token);
}

std::string error_of(const ApiResponse& r) {
  try {
    const nlohmann::json j = nlohmann::json::parse(r.body);
    if (j.is_object() && j.contains("error")) return j["error"].get<std::string>();
  } catch (const std::exception&) {
  }
  return "";
}

}  // namespace cathbox::server::test
