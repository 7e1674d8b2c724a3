#include "session/record_header.hpp"

#include <cmath>

#include "record_header_device.hpp"
#include "record_header_fields.hpp"
#include "record_header_tool.hpp"
#include "session/record_format.hpp"

namespace cathbox::session {
namespace {

using record::ByteReader;
using record::ByteWriter;
using record::FieldError;
using record::Fields;
using record::get_u64;
using record::t;
using record::text_of;

constexpr std::size_t kMaxText = 64u << 20;  // a header field (the HCLM text is the largest)

}  // namespace

std::vector<std::uint8_t> encode_header(const RecordHeader& h) {
  std::vector<std::uint8_t> out;
  ByteWriter w(out);
  using record::HeaderTag;
  w.field_text(t(HeaderTag::kSoftwareVersion), h.software_version);
  w.field_u64(t(HeaderTag::kStartUnix_us), static_cast<std::uint64_t>(h.start_unix_us));
  w.field_text(t(HeaderTag::kCaseName), h.case_name);
  w.field_text(t(HeaderTag::kCaseFile), h.case_file);
  w.field_text(t(HeaderTag::kCaseText), h.case_text);
  w.field_text(t(HeaderTag::kVesselFile), h.vessel_file);
  w.field_text(t(HeaderTag::kVesselText), h.vessel_text);
  if (!h.surface_file.empty()) {
    w.field_text(t(HeaderTag::kSurfaceFile), h.surface_file);
    w.field_text(t(HeaderTag::kSurfaceBytes), h.surface_bytes);
  }
  for (const tool::ToolSpec& spec : h.tools) w.field(t(HeaderTag::kTool), record::encode_tool(spec));
  std::vector<std::uint8_t> entry;
  ByteWriter we(entry);
  for (int i = 0; i < 3; ++i) we.f64(h.entry.point_mm[i]);
  for (int i = 0; i < 3; ++i) we.f64(h.entry.direction[i]);
  w.field(t(HeaderTag::kEntry), entry);
  w.field_u64(t(HeaderTag::kHeldTool), h.held_tool);
  w.field_u64(t(HeaderTag::kHandKind), static_cast<std::uint64_t>(h.hand));
  w.field_text(t(HeaderTag::kHandDescription), h.hand_description);
  if (h.device) w.field(t(HeaderTag::kDevice), record::encode_device(*h.device));
  w.field_u64(t(HeaderTag::kPeriod_us), static_cast<std::uint64_t>(h.period_us));
  w.field_u64(t(HeaderTag::kHashEvery), static_cast<std::uint64_t>(h.hash_every));
  return out;
}

namespace {

// Which of the header's required fields were seen.
struct Seen {
  bool entry = false;
  bool held = false;
  bool hand = false;
};

int decode_entry(std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, FieldError& err) {
  ByteReader r(v);
  double x[6];
  for (double& c : x) {
    if (v.size() != 48 || !r.f64(c) || !std::isfinite(c)) return err.bad(at, "header: entry is not 6 finite doubles");
  }
  h.entry.point_mm = {x[0], x[1], x[2]};
  h.entry.direction = {x[3], x[4], x[5]};
  return 1;
}

// A text field of at most kMaxText bytes.
int decode_text(std::span<const std::uint8_t> v, std::size_t at, std::string& out, const char* too_long, FieldError& err) {
  if (v.size() > kMaxText) return err.bad(at, too_long);
  out = text_of(v);
  return 1;
}

int decode_header_field(std::uint64_t tag, std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, Seen& seen,
                        FieldError& err) {
  using record::HeaderTag;
  std::uint64_t u = 0;
  switch (static_cast<HeaderTag>(tag)) {
    case HeaderTag::kSoftwareVersion: h.software_version = text_of(v); return 1;
    case HeaderTag::kStartUnix_us:
      if (!get_u64(v, u)) return err.bad(at, "header: start time is not 8 bytes");
      h.start_unix_us = static_cast<std::int64_t>(u);
      return 1;
    case HeaderTag::kCaseName: h.case_name = text_of(v); return 1;
    case HeaderTag::kCaseFile: h.case_file = text_of(v); return 1;
    case HeaderTag::kCaseText: return decode_text(v, at, h.case_text, "header: case text too long", err);
    case HeaderTag::kVesselFile: h.vessel_file = text_of(v); return 1;
    case HeaderTag::kVesselText: return decode_text(v, at, h.vessel_text, "header: vessel text too long", err);
    case HeaderTag::kSurfaceFile: h.surface_file = text_of(v); return 1;
    case HeaderTag::kSurfaceBytes: return decode_text(v, at, h.surface_bytes, "header: surface too long", err);
    case HeaderTag::kTool: return record::decode_tool(v, at, h, err);
    case HeaderTag::kEntry: seen.entry = true; return decode_entry(v, at, h, err);
    case HeaderTag::kHeldTool:
      if (!get_u64(v, u) || u >= kMaxTools) return err.bad(at, "header: held tool out of range");
      h.held_tool = static_cast<std::size_t>(u);
      seen.held = true;
      return 1;
    case HeaderTag::kHandKind:
      if (!get_u64(v, u) || u < 1 || u > 6) return err.bad(at, "header: unknown hand kind");
      h.hand = static_cast<HandKind>(u);
      seen.hand = true;
      return 1;
    case HeaderTag::kHandDescription: h.hand_description = text_of(v); return 1;
    case HeaderTag::kDevice: return record::decode_device(v, at, h, err);
    case HeaderTag::kPeriod_us:
      if (!get_u64(v, u) || u < 100 || u > 100'000) return err.bad(at, "header: tick period must be 100..100000 us");
      h.period_us = static_cast<std::int64_t>(u);
      return 1;
    case HeaderTag::kHashEvery:
      if (!get_u64(v, u) || u < 1 || u > 1'000'000) return err.bad(at, "header: hash interval must be 1..1000000 ticks");
      h.hash_every = static_cast<std::int64_t>(u);
      return 1;
  }
  return 0;
}

// The header's fields together: tools, required fields, held tool in range.
bool check_header(const RecordHeader& h, const Seen& seen, std::string& what) {
  if (h.tools.empty()) return what = "header: no tools", false;
  if (!seen.entry || !seen.held || !seen.hand || h.period_us == 0 || h.hash_every == 0) {
    return what = "header: a required field is missing (entry, held tool, hand, period, hash interval)", false;
  }
  if (h.held_tool >= h.tools.size()) return what = "header: held tool beyond the tools", false;
  if (const std::string e = tool::check_tools(h.tools); !e.empty()) return what = "header: " + e, false;
  return true;
}

}  // namespace

bool decode_header(std::span<const std::uint8_t> data, RecordHeader& out, std::string& what, std::size_t& offset) {
  RecordHeader h;
  h.period_us = 0;
  h.hash_every = 0;
  Seen seen;
  FieldError err;
  Fields top(data, 0);
  const bool ok = top.each("header", [&](std::uint64_t tag, std::span<const std::uint8_t> v, std::size_t at) {
    return decode_header_field(tag, v, at, h, seen, err);
  });
  if (!ok) {
    what = err.what.empty() ? top.what_ : err.what;
    offset = err.what.empty() ? top.offset_ : err.at;
    return false;
  }
  offset = data.size();
  if (!check_header(h, seen, what)) return false;
  out = std::move(h);
  return true;
}

}  // namespace cathbox::session
