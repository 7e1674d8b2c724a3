#include <nlohmann/json.hpp>

#include "server/case_bundle.hpp"
#include "server/client.hpp"
#include "server/json_input.hpp"
#include "server/sha256.hpp"
#include "server/zstd_codec.hpp"

namespace cathbox::server {

namespace {

Error answer_error(const HttpAnswer& a) { return make_error(a.status == 0 ? 503 : a.status, a.problem()); }

Result<nlohmann::json> json_of(const HttpAnswer& a, int expected) {
  if (a.status != expected) return answer_error(a);
  Result<nlohmann::json> j = parse_json_object(a.body, "answer");
  if (!j) return make_error(502, j.error().message);
  return j;
}

}  // namespace

ServerClient::ServerClient(std::string base_url, int timeout_ms) : base_url_(std::move(base_url)), http_(base_url_, timeout_ms) {}

Status ServerClient::login(const std::string& name, const std::string& password) {
  const nlohmann::json body = {{"name", name}, {"password", password}};
  Result<nlohmann::json> j = json_of(http_.post_json("/api/v1/login", body.dump()), 200);
  if (!j) return j.error();
  const auto token = j.value().find("token");
  if (token == j.value().end() || !token->is_string()) return make_error(502, "login: answer without a token");
  http_.set_token(token->get<std::string>());
  return Ok{};
}

Result<std::vector<AssignmentInfo>> ServerClient::assignments() {
  Result<nlohmann::json> j = json_of(http_.get("/api/v1/assignments"), 200);
  if (!j) return j.error();
  std::vector<AssignmentInfo> out;
  try {
    for (const auto& a : j.value().at("assignments")) {
      AssignmentInfo info;
      info.id = a.at("id").get<std::int64_t>();
      info.case_name = a.at("case").get<std::string>();
      info.case_version = a.at("case_version").is_number() ? a.at("case_version").get<int>() : 0;
      info.note = a.value("note", "");
      info.criteria_json = a.at("criteria").dump();
      info.due_at = a.at("due_at").is_string() ? a.at("due_at").get<std::string>() : "";
      out.push_back(std::move(info));
    }
  } catch (const nlohmann::json::exception& e) {
    return make_error(502, std::string("assignments: unexpected answer: ") + e.what());
  }
  return out;
}

Result<std::vector<CaseInfo>> ServerClient::cases() {
  Result<nlohmann::json> j = json_of(http_.get("/api/v1/cases"), 200);
  if (!j) return j.error();
  std::vector<CaseInfo> out;
  try {
    for (const auto& c : j.value().at("cases")) {
      CaseInfo info;
      info.name = c.at("name").get<std::string>();
      info.version = c.at("version").get<int>();
      info.title = c.at("title").get<std::string>();
      info.content_hash = c.at("content_hash").get<std::string>();
      info.wire_bytes = c.at("sizes").at("wire_bytes").get<std::int64_t>();
      info.mesh_bytes = c.at("sizes").at("mesh_bytes").get<std::int64_t>();
      out.push_back(std::move(info));
    }
  } catch (const nlohmann::json::exception& e) {
    return make_error(502, std::string("cases: unexpected answer: ") + e.what());
  }
  return out;
}

Result<std::string> ServerClient::download_case(const std::string& name, int version, const std::string& folder) {
  if (const std::string bad = check_slug(name); !bad.empty()) return make_error(400, "case " + bad);
  const std::string v = version == 0 ? "latest" : std::to_string(version);
  const HttpAnswer a = http_.request("GET", "/api/v1/cases/" + name + "/versions/" + v + "/bundle", {}, {{"Accept-Encoding", "zstd"}});
  if (a.status != 200) return answer_error(a);
  std::string json = a.body;
  if (a.header("content-encoding") == "zstd") {
    Result<std::string> plain = zstd_decompress(a.body, kMaxBundleBytes * 2);
    if (!plain) return make_error(502, "case bundle: " + plain.error().message);
    json = std::move(plain.value());
  }
  std::string etag = a.header("etag");
  if (etag.size() >= 2 && etag.front() == '"') etag = etag.substr(1, etag.size() - 2);
  if (!etag.empty() && sha256_hex(json) != etag) return make_error(502, "case bundle: content does not match its hash (corrupted in transit)");
  Result<CaseBundle> bundle = parse_bundle_json(json);
  if (!bundle) return make_error(502, bundle.error().message);
  const std::string got_version = a.header("x-cathbox-case-version");
  return write_bundle_files(bundle.value(), folder + "/" + name + "-v" + (got_version.empty() ? v : got_version));
}

UploadOutcome ServerClient::upload_record(const std::string& bytes, std::optional<std::int64_t> assignment_id) {
  std::string target = "/api/v1/results";
  if (assignment_id) target += "?assignment=" + std::to_string(*assignment_id);
  const HttpAnswer a = http_.request("POST", target, bytes, {{"Content-Type", "application/octet-stream"}});
  UploadOutcome out;
  out.message = a.problem();
  if (a.status == 201 || a.status == 200) {
    out.verdict = a.status == 201 ? UploadVerdict::kStored : UploadVerdict::kDuplicate;
    try {
      out.result_id = nlohmann::json::parse(a.body).at("id").get<std::int64_t>();
    } catch (const std::exception&) {
    }
    out.message.clear();
  } else if (a.status == 401) {
    out.verdict = UploadVerdict::kUnauthorized;
  } else if (a.status >= 400 && a.status < 500 && a.status != 408 && a.status != 429) {
    out.verdict = UploadVerdict::kRefused;
  } else {
    out.verdict = UploadVerdict::kRetryLater;
  }
  return out;
}

}  // namespace cathbox::server
