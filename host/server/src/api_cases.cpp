// GET /cases, POST /cases, GET /cases/{name}, GET /cases/{name}/versions/{v}[/bundle]
#include <charconv>

#include "api_call.hpp"
#include "server/iso_time.hpp"
#include "server/json_input.hpp"
#include "server/zstd_codec.hpp"

namespace cathbox::server::api {

namespace {

double ratio(std::int64_t a, std::int64_t b) { return b > 0 ? static_cast<double>(a) / static_cast<double>(b) : 0.0; }

// Whether an Accept-Encoding header admits `coding` (a q=0 refuses it).
bool accepts(std::string_view header, std::string_view coding) {
  while (!header.empty()) {
    const std::size_t comma = header.find(',');
    std::string_view item = header.substr(0, comma);
    header = comma == std::string_view::npos ? std::string_view() : header.substr(comma + 1);
    const std::size_t semi = item.find(';');
    std::string_view token = item.substr(0, semi);
    while (!token.empty() && token.front() == ' ') token.remove_prefix(1);
    while (!token.empty() && token.back() == ' ') token.remove_suffix(1);
    if (token != coding && token != "*") continue;
    if (semi == std::string_view::npos) return true;
    std::string_view params = item.substr(semi + 1);
    const std::size_t q = params.find("q=");
    if (q == std::string_view::npos) return true;
    params = params.substr(q + 2);
    return !(params.rfind("0", 0) == 0 && params.find_first_of("123456789") == std::string_view::npos);
  }
  return false;
}

std::string version_url(const CaseVersion& v) { return "/api/v1/cases/" + v.name + "/versions/" + std::to_string(v.version); }

Result<CaseVersion> find_version(Call& call) {
  int version = 0;
  const std::string& v = call.params[1];
  if (v != "latest") {
    std::int64_t n = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
    if (v.empty() || ec != std::errc() || end != v.data() + v.size() || n < 1 || n > 1'000'000) {
      return make_error(400, "path: version must be a number from 1 or 'latest'");
    }
    version = static_cast<int>(n);
  }
  std::optional<CaseVersion> found = call.c.store.case_version(call.params[0], version);
  if (!found) return make_error(404, "no case '" + call.params[0] + "' version " + v);
  return *found;
}

// The stored bundle of a version: its zstd bytes, or the JSON text when `decompress`.
Result<std::string> stored_bundle(Call& call, const CaseVersion& v, bool decompress) {
  std::optional<std::string> wire = call.c.store.case_bundle(v.id);
  if (!wire) return make_error(404, "case bundle missing");
  if (!decompress) return std::move(*wire);
  Result<std::string> plain = zstd_decompress(*wire, kMaxBundleBytes * 2);
  if (!plain) return make_error(500, "stored bundle unreadable: " + plain.error().message);
  return plain;
}

}  // namespace

nlohmann::json case_json(const CaseVersion& v) {
  return {{"name", v.name},
          {"version", v.version},
          {"title", v.title},
          {"case_file", v.case_file},
          {"hclm_file", v.hclm_file},
          {"content_hash", v.content_hash},
          {"created_at", iso_time(v.created_us)},
          {"sizes",
           {{"raw_bytes", v.raw_bytes},
            {"wire_bytes", v.wire_bytes},
            {"mesh_vertices", v.mesh_vertices},
            {"mesh_triangles", v.mesh_triangles},
            {"mesh_bytes", v.mesh_bytes},
            {"mesh_to_wire", ratio(v.mesh_bytes, v.wire_bytes)},
            {"raw_to_wire", ratio(v.raw_bytes, v.wire_bytes)}}},
          {"bundle_url", version_url(v) + "/bundle"}};
}

Reply list_cases(Call& call) {
  nlohmann::json cases = nlohmann::json::array();
  for (const CaseVersion& v : call.c.store.list_cases()) cases.push_back(case_json(v));
  return json_response(200, {{"cases", std::move(cases)}});
}

Reply upload_case(Call& call) {
  if (Status s = call.require_supervisor("uploading cases"); !s) return s.error();
  Result<nlohmann::json> body = call.json_body();
  if (!body) return body.error();
  FieldReader f(body.value());
  const std::string name = f.string("name", 64);
  CaseBundle b;
  b.case_file = f.string("case_file", 64);
  b.case_text = f.string("case", kMaxCaseTextBytes);
  b.hclm_file = f.optional_string("hclm_file", 64).value_or("");
  b.hclm_text = f.optional_string("hclm", kMaxHclmBytes).value_or("");
  b.surface_file = f.optional_string("surface_file", 64).value_or("");
  const std::string surface_hex = f.optional_string("surface_hex", kMaxBundleBytes).value_or("");
  f.only({"name", "case_file", "case", "hclm_file", "hclm", "surface_file", "surface_hex"});
  if (!f.ok()) return f.error();
  if (std::optional<std::string> bytes = bytes_of_hex(surface_hex)) b.surface_bytes = std::move(*bytes);
  else return make_error(400, "field 'surface_hex': not lowercase hex of whole bytes");
  if (!f.ok()) return f.error();
  Result<CaseUploadOutcome> up = call.c.cases.upload(name, b, call.caller.user_id, call.c.clock.now_us());
  if (!up) return up.error();
  if (up.value().created) audit(call, "case.upload", name, "version=" + std::to_string(up.value().version.version));
  nlohmann::json j = case_json(up.value().version);
  j["created"] = up.value().created;
  ApiResponse r = json_response(up.value().created ? 201 : 200, j);
  r.headers.emplace_back("Location", version_url(up.value().version));
  return r;
}

Reply case_versions(Call& call) {
  nlohmann::json versions = nlohmann::json::array();
  for (const CaseVersion& v : call.c.store.case_versions(call.params[0])) versions.push_back(case_json(v));
  if (versions.empty()) return make_error(404, "no case '" + call.params[0] + "'");
  return json_response(200, {{"name", call.params[0]}, {"versions", std::move(versions)}});
}

Reply case_version(Call& call) {
  Result<CaseVersion> v = find_version(call);
  if (!v) return v.error();
  return json_response(200, case_json(v.value()));
}

Reply case_bundle(Call& call) {
  Result<CaseVersion> v = find_version(call);
  if (!v) return v.error();
  const std::string etag = "\"" + v.value().content_hash + "\"";
  ApiResponse r;
  r.headers.emplace_back("ETag", etag);
  r.headers.emplace_back("X-Cathbox-Case", v.value().name);
  r.headers.emplace_back("X-Cathbox-Case-Version", std::to_string(v.value().version));
  r.headers.emplace_back("Vary", "Accept-Encoding");
  // Only for this user's cache, and asked again each time (a 304 when unchanged).
  r.headers.emplace_back("Cache-Control", "private, no-cache");
  if (call.request.if_none_match == etag) {
    r.status = 304;
    r.content_type.clear();
    return r;
  }
  const bool zstd = accepts(call.request.accept_encoding, "zstd");
  Result<std::string> body = stored_bundle(call, v.value(), !zstd);
  if (!body) return body.error();
  if (zstd) r.headers.emplace_back("Content-Encoding", "zstd");
  r.body = std::move(body.value());
  return r;
}

Reply case_mesh(Call& call) {
  Result<CaseVersion> v = find_version(call);
  if (!v) return v.error();
  // ?level=collision: the surface the session's collision tree is built on, every field exact
  // (CBXMESH2), for the WebAssembly session; else the coarse surface to draw (CBXMESH1).
  const std::optional<std::string> level = call.query("level");
  if (level && *level != "collision" && *level != "view") {
    return make_error(400, "query 'level': '" + level->substr(0, 32) + "' is neither 'collision' nor 'view'");
  }
  const bool collision = level && *level == "collision";
  const std::string kind = collision ? "mesh2" : "mesh1";
  // A version's mesh never changes: browsers keep it and ask again with its ETag (304).
  const std::string etag = "\"" + kind + "-" + v.value().content_hash + "\"";
  const auto validators = [&](ApiResponse& r) {
    r.headers.emplace_back("ETag", etag);
    r.headers.emplace_back("Cache-Control", "private, no-cache");
  };
  if (call.request.if_none_match == etag) {
    ApiResponse r;
    r.status = 304;
    r.content_type.clear();
    validators(r);
    return r;
  }
  // Meshed once per content (the cache key is the bundle's hash), on first request.
  Result<std::shared_ptr<const std::string>> mesh = cached(call, kind + ":" + v.value().content_hash, [&]() -> Result<std::string> {
    Result<std::string> json = stored_bundle(call, v.value(), true);
    if (!json) return json.error();
    Result<CaseBundle> bundle = parse_bundle_json(json.value());
    if (!bundle) return bundle.error();
    return collision ? collision_mesh(bundle.value()) : browser_mesh(bundle.value());
  });
  if (!mesh) return mesh.error();
  ApiResponse r;
  r.content_type = "application/octet-stream";
  r.body = *mesh.value();
  r.headers.emplace_back("X-Cathbox-Case", v.value().name);
  r.headers.emplace_back("X-Cathbox-Case-Version", std::to_string(v.value().version));
  validators(r);
  return r;
}

}  // namespace cathbox::server::api
