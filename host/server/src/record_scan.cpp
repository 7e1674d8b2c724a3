#include "record_scan.hpp"

#include <openssl/evp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <stdexcept>
#include <vector>

#include "scenario/case_file.hpp"
#include "scenario/case_world.hpp"
#include "session/record_reader.hpp"
#include "tool/mesh_wall.hpp"

namespace cathbox::server {
namespace {

// SHA-256 fed piece by piece (OpenSSL's digest context).
class Digest {
 public:
  Digest() : ctx_(EVP_MD_CTX_new(), EVP_MD_CTX_free) {
    if (!ctx_ || EVP_DigestInit_ex(ctx_.get(), EVP_sha256(), nullptr) != 1) throw std::runtime_error("OpenSSL SHA-256 failed");
  }
  void bytes(const void* data, std::size_t n) { (void)EVP_DigestUpdate(ctx_.get(), data, n); }
  void u64(std::uint64_t v) {
    unsigned char b[8];
    for (int i = 0; i < 8; ++i) b[i] = static_cast<unsigned char>(v >> (8 * i));
    bytes(b, 8);
  }
  void i64(std::int64_t v) { u64(static_cast<std::uint64_t>(v)); }
  void f64(double v) {
    std::uint64_t bits = 0;
    std::memcpy(&bits, &v, 8);
    u64(bits);
  }
  // Length first: "ab"+"c" and "a"+"bc" differ.
  void text(std::string_view s) {
    u64(s.size());
    bytes(s.data(), s.size());
  }
  void blob(const std::vector<std::uint8_t>& b) {
    u64(b.size());
    bytes(b.data(), b.size());
  }
  std::string hex() {
    unsigned char digest[EVP_MAX_MD_SIZE];
    unsigned int length = 0;
    (void)EVP_DigestFinal_ex(ctx_.get(), digest, &length);
    static constexpr char kHex[] = "0123456789abcdef";
    std::string out;
    for (unsigned int i = 0; i < length; ++i) {
      out += kHex[digest[i] >> 4];
      out += kHex[digest[i] & 15];
    }
    return out;
  }

 private:
  std::unique_ptr<EVP_MD_CTX, void (*)(EVP_MD_CTX*)> ctx_;
};

// A tool as the record encodes it (the header's tool field alone): equal specifications, equal bytes.
std::vector<std::uint8_t> tool_bytes(const tool::ToolSpec& spec) {
  session::RecordHeader h;
  h.tools = {spec};
  return session::encode_header(h);
}

std::string entry_text(const tool::Entry& e) {
  const auto num = [](double v) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", v);
    return std::string(b);
  };
  return num(e.point_mm.x) + " " + num(e.point_mm.y) + " " + num(e.point_mm.z) + ", direction " + num(e.direction.x) + " " +
         num(e.direction.y) + " " + num(e.direction.z);
}

// The case file's plain name, for messages.
std::string case_label(const session::RecordHeader& h) {
  return h.case_file.empty() ? std::string("a bare vessel file") : std::filesystem::path(h.case_file).filename().string();
}

bool same_entry(const tool::Entry& a, const tool::Entry& b) {
  // The record stores the entry's doubles as they were: the same case gives the same bits. The
  // tolerance only absorbs a last-bit difference of the default entry's stepping.
  constexpr double kEpsilon = 1e-9;
  for (int i = 0; i < 3; ++i) {
    if (std::abs(a.point_mm[i] - b.point_mm[i]) > kEpsilon || std::abs(a.direction[i] - b.direction[i]) > kEpsilon) return false;
  }
  return true;
}

}  // namespace

Result<RecordScan> scan_record(std::string_view bytes, const UploadLimits& limits) {
  auto reader = session::RecordReader::from_bytes(std::vector<std::uint8_t>(bytes.begin(), bytes.end()), "record");
  if (!reader) return make_error(422, reader.error().message);
  const session::RecordHeader& h = (*reader)->header();
  if (h.period_us <= 0) return make_error(422, "record: header field 'period_us': " + std::to_string(h.period_us) + " is not a tick period");
  Digest d;
  // The run: what the replay rebuilds the session from (not the informational fields: software
  // version, hand kind and description, the device).
  d.text(h.case_text);
  d.text(h.vessel_text);
  d.u64(h.tools.size());
  for (const tool::ToolSpec& t : h.tools) d.blob(tool_bytes(t));
  for (int i = 0; i < 3; ++i) d.f64(h.entry.point_mm[i]);
  for (int i = 0; i < 3; ++i) d.f64(h.entry.direction[i]);
  d.u64(h.held_tool);
  d.i64(h.period_us);
  d.i64(h.hash_every);
  d.i64(h.start_unix_us);
  const std::size_t tools = std::min(h.tools.size(), session::kMaxTools);
  const std::int64_t max_ticks = limits.max_record_duration_s * 1'000'000 / h.period_us;
  RecordScan out;
  session::TickRecord t;
  while ((*reader)->next(t)) {
    if (++out.ticks > max_ticks) {
      return make_error(413, "record: longer than the limit of " + std::to_string(limits.max_record_duration_s) + " s of simulated time (" +
                                 std::to_string(max_ticks) + " ticks of " + std::to_string(h.period_us) + " us)");
    }
    d.i64(t.tick);
    for (std::size_t i = 0; i < tools; ++i) {
      d.i64(t.tools[i].insertion_um);
      d.i64(t.tools[i].rotation_urad);
    }
    d.u64(t.control_count);
    for (std::size_t i = 0; i < t.control_count; ++i) {
      d.u64(t.controls[i].kind);
      d.u64(t.controls[i].size);
      d.bytes(t.controls[i].payload.data(), t.controls[i].size);
    }
    d.u64(t.state_hash ? 1 : 0);
    d.u64(t.state_hash.value_or(0));
  }
  if (!(*reader)->error().empty()) return make_error(422, (*reader)->error());
  out.complete = (*reader)->finished();
  d.u64(out.complete ? 1 : 0);
  out.run_hash = d.hex();
  return out;
}

Status check_header_tools(const session::RecordHeader& h) {
  std::vector<tool::ToolSpec> expected;
  if (h.case_text.empty()) {
    expected = {tool::default_guidewire()};
  } else {
    const tool::CaseParse parsed = tool::parse_case(h.case_text, h.case_file);
    if (!parsed) return make_error(422, "record: the record's case: " + parsed.error().message);
    expected = parsed->tools;
  }
  const std::string label = case_label(h);
  if (h.tools.size() != expected.size()) {
    return make_error(422, "record: header field 'tools': " + std::to_string(h.tools.size()) + " tools, but " + label + " defines " +
                               std::to_string(expected.size()));
  }
  for (std::size_t i = 0; i < expected.size(); ++i) {
    if (tool_bytes(h.tools[i]) == tool_bytes(expected[i])) continue;
    const std::string which = "tool " + std::to_string(i + 1) + " '" + h.tools[i].name.substr(0, 64) + "'";
    if (h.tools[i].name != expected[i].name) {
      return make_error(422, "record: header field 'tools': " + which + " is not the tool " + label + " defines there ('" +
                                 expected[i].name + "')");
    }
    return make_error(422, "record: header field 'tools': " + which + " is not as " + label + " defines it");
  }
  return Ok{};
}

Status check_header_entry(const session::RecordHeader& h, const session::SessionCase& scene) {
  std::optional<tool::Entry> expected;
  if (!h.case_text.empty()) {
    const tool::CaseParse parsed = tool::parse_case(h.case_text, h.case_file);
    if (!parsed) return make_error(422, "record: the record's case: " + parsed.error().message);
    expected = parsed->entry;
  }
  if (!expected) {
    const auto* wall = scene.world ? dynamic_cast<const tool::MeshWall*>(&scene.world->wall()) : nullptr;
    if (wall == nullptr || scene.model() == nullptr) return make_error(422, "record: header field 'entry': the case defines no entry");
    expected = tool::default_entry(*scene.model(), wall->tree());
    if (!expected) return make_error(422, "record: header field 'entry': the vessel has no root segment to enter");
  }
  if (!same_entry(h.entry, *expected)) {
    return make_error(422, "record: header field 'entry' (" + entry_text(h.entry) + ") is not the entry of " + case_label(h) + " (" +
                               entry_text(*expected) + ")");
  }
  return Ok{};
}

}  // namespace cathbox::server
