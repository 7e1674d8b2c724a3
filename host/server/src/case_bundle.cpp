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

std::string hex_of(std::string_view bytes) {
  static constexpr char kDigits[] = "0123456789abcdef";
  std::string out;
  out.reserve(bytes.size() * 2);
  for (const char c : bytes) {
    const auto u = static_cast<unsigned char>(c);
    out.push_back(kDigits[u >> 4U]);
    out.push_back(kDigits[u & 15U]);
  }
  return out;
}

std::optional<std::string> bytes_of_hex(std::string_view hex) {
  if (hex.size() % 2 != 0) return std::nullopt;
  const auto digit = [](char c) -> int {
    if (c >= '0' && c <= '9') return c - '0';
    if (c >= 'a' && c <= 'f') return c - 'a' + 10;
    return -1;
  };
  std::string out(hex.size() / 2, '\0');
  for (std::size_t i = 0; i < out.size(); ++i) {
    const int hi = digit(hex[2 * i]);
    const int lo = digit(hex[2 * i + 1]);
    if (hi < 0 || lo < 0) return std::nullopt;
    out[i] = static_cast<char>(hi * 16 + lo);
  }
  return out;
}

std::string bundle_json(const CaseBundle& b) {
  const nlohmann::json j = {{"format", "cathbox-case-bundle 1"}, {"case_file", b.case_file}, {"case", b.case_text},
                            {"hclm_file", b.hclm_file}, {"hclm", b.hclm_text}};
  if (b.surface_file.empty()) return j.dump();  // as before surfaces: existing cases keep their hash
  nlohmann::json with_surface = j;
  with_surface["surface_file"] = b.surface_file;
  with_surface["surface_hex"] = hex_of(b.surface_bytes);
  return with_surface.dump();
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
  b.surface_file = f.optional_string("surface_file", 64).value_or("");
  const std::string surface_hex = f.optional_string("surface_hex", kMaxBundleBytes).value_or("");
  if (f.ok() && b.surface_file.empty() != surface_hex.empty()) f.fail("surface_file", "surface_file and surface_hex come together");
  if (f.ok() && !b.surface_file.empty()) {
    if (std::optional<std::string> bytes = bytes_of_hex(surface_hex)) b.surface_bytes = std::move(*bytes);
    else f.fail("surface_hex", "not lowercase hex of whole bytes");
  }
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
  if (!b.surface_file.empty()) {
    if (Status s = write_file(dir / b.surface_file, b.surface_bytes); !s) return s.error();
  }
  if (Status s = write_file(dir / b.case_file, b.case_text); !s) return s.error();
  return (dir / b.case_file).string();
}

}  // namespace cathbox::server
