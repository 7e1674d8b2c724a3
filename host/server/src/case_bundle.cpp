#include "server/case_bundle.hpp"

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "server/json_input.hpp"

namespace cathbox::server {

namespace {
bool plain_file_name(const std::string& name) {
  return check_slug(name).empty() && name != "." && name != "..";
}

Status write_file(const std::filesystem::path& path, const std::string& text) {
  const std::filesystem::path tmp = path.string() + ".part";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    if (!out) return make_error(500, tmp.string() + ": cannot write");
  }
  std::error_code ec;
  std::filesystem::rename(tmp, path, ec);
  if (ec) return make_error(500, path.string() + ": " + ec.message());
  return Ok{};
}
}  // namespace

std::string bundle_json(const CaseBundle& b) {
  const nlohmann::json j = {{"format", "cathbox-case-bundle 1"}, {"case_file", b.case_file}, {"case", b.case_text},
                            {"hclm_file", b.hclm_file}, {"hclm", b.hclm_text}};
  return j.dump();
}

Result<CaseBundle> parse_bundle_json(const std::string& json_text) {
  Result<nlohmann::json> parsed = parse_json_object(json_text, "bundle");
  if (!parsed) return make_error(422, parsed.error().message);
  FieldReader f(parsed.value(), "bundle.");
  CaseBundle b;
  if (f.string("format", 64) != "cathbox-case-bundle 1" && f.ok()) f.fail("format", "not 'cathbox-case-bundle 1'");
  b.case_file = f.string("case_file", 64);
  b.case_text = f.string("case", kMaxBundleBytes);
  b.hclm_file = f.optional_string("hclm_file", 64).value_or("");
  b.hclm_text = f.optional_string("hclm", kMaxBundleBytes).value_or("");
  if (f.ok() && !plain_file_name(b.case_file)) f.fail("case_file", "not a plain file name");
  if (f.ok() && !b.hclm_file.empty() && !plain_file_name(b.hclm_file)) f.fail("hclm_file", "not a plain file name");
  if (!f.ok()) return make_error(422, f.error().message);
  return b;
}

Result<std::string> write_bundle_files(const CaseBundle& b, const std::string& folder) {
  std::error_code ec;
  std::filesystem::create_directories(folder, ec);
  if (ec) return make_error(500, folder + ": " + ec.message());
  const std::filesystem::path dir(folder);
  if (!b.hclm_file.empty()) {
    if (Status s = write_file(dir / b.hclm_file, b.hclm_text); !s) return s.error();
  }
  if (Status s = write_file(dir / b.case_file, b.case_text); !s) return s.error();
  return (dir / b.case_file).string();
}

}  // namespace cathbox::server
