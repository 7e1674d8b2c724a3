#include "session/record_header.hpp"

#include <cmath>

#include "session/record_format.hpp"

namespace cathbox::session {
namespace {

using record::ByteReader;
using record::ByteWriter;

constexpr std::size_t kMaxText = 64u << 20;  // a header field (the HCLM text is the largest)

template <class Tag>
std::uint32_t t(Tag tag) {
  return static_cast<std::uint32_t>(tag);
}

std::vector<std::uint8_t> encode_section(const tool::ToolSection& s) {
  std::vector<std::uint8_t> sec;
  ByteWriter ws(sec);
  ws.f64(s.length_mm);
  ws.f64(s.outer_diameter_mm);
  ws.f64(s.bending_stiffness_Nmm2);
  ws.f64(s.torsion_stiffness_Nmm2);
  ws.f64(s.curve_deg);
  if (s.shape != tool::CoilShape::kNone) {  // a coil's secondary shape: 7 doubles
    ws.f64(static_cast<double>(s.shape));
    ws.f64(s.loop_diameter_mm);
  }
  return sec;
}

std::vector<std::uint8_t> encode_tool(const tool::ToolSpec& spec) {
  std::vector<std::uint8_t> out;
  ByteWriter w(out);
  using record::ToolTag;
  w.field_text(t(ToolTag::kName), spec.name);
  const std::uint8_t kind = static_cast<std::uint8_t>(spec.kind);
  w.field(t(ToolTag::kKind), std::span(&kind, 1));
  for (const tool::ToolSection& s : spec.sections) w.field(t(ToolTag::kSection), encode_section(s));
  for (const tool::ToolSection& s : spec.next_coils) w.field(t(ToolTag::kNextCoil), encode_section(s));
  w.field_f64(t(ToolTag::kFriction), spec.friction);
  w.field_f64(t(ToolTag::kInnerDiameter), spec.inner_diameter_mm);
  w.field_f64(t(ToolTag::kAxialStiffness), spec.axial_stiffness_N);
  if (spec.drag_mN_s_per_mm2) w.field_f64(t(ToolTag::kDrag), *spec.drag_mN_s_per_mm2);
  w.field_f64(t(ToolTag::kBloodViscosity), spec.blood_viscosity_mPa_s);
  if (spec.valve_friction_mN) w.field_f64(t(ToolTag::kValveFriction), *spec.valve_friction_mN);
  w.field_f64(t(ToolTag::kMaxSpacing), spec.max_spacing_mm);
  w.field_f64(t(ToolTag::kTipSpacing), spec.tip_spacing_mm);
  w.field_f64(t(ToolTag::kTipZone), spec.tip_zone_mm);
  if (!spec.inside.empty()) w.field_text(t(ToolTag::kInside), spec.inside);
  if (spec.detach_mm > 0.0) w.field_f64(t(ToolTag::kDetach), spec.detach_mm);
  if (spec.balloon.present()) {
    std::vector<std::uint8_t> b;
    ByteWriter wb(b);
    for (const double v : {spec.balloon.length_mm, spec.balloon.from_tip_mm, spec.balloon.nominal_atm, spec.balloon.rated_burst_atm}) wb.f64(v);
    for (std::size_t i = 0; i < spec.balloon.pressure_atm.size(); ++i) {
      wb.f64(spec.balloon.pressure_atm[i]);
      wb.f64(spec.balloon.diameter_mm[i]);
    }
    w.field(t(ToolTag::kBalloon), b);
  }
  if (spec.stent.present()) {
    std::vector<std::uint8_t> b;
    ByteWriter wb(b);
    for (const double v : {spec.stent.diameter_mm, spec.stent.length_mm, spec.stent.embed_s}) wb.f64(v);
    w.field(t(ToolTag::kStentRetriever), b);
  }
  return out;
}

std::vector<std::uint8_t> encode_device(const DeviceRecord& d) {
  std::vector<std::uint8_t> out;
  ByteWriter w(out);
  using record::DeviceTag;
  w.field_text(t(DeviceTag::kDescription), d.description);
  w.field_text(t(DeviceTag::kSerial), d.serial);
  w.field_text(t(DeviceTag::kBoard), d.board);
  w.field_text(t(DeviceTag::kFirmware), d.firmware);
  w.field_u64(t(DeviceTag::kInsertionCountsPerM), d.insertion_counts_per_m);
  w.field_u64(t(DeviceTag::kRotationCountsPerRev), d.rotation_counts_per_rev);
  w.field_u64(t(DeviceTag::kInsertionFullScaleMn), d.insertion_full_scale_mN);
  w.field_u64(t(DeviceTag::kRotationFullScaleUnm), d.rotation_full_scale_uNm);
  w.field_u64(t(DeviceTag::kInsertionActuator), d.insertion_actuator);
  w.field_u64(t(DeviceTag::kRotationActuator), d.rotation_actuator);
  return out;
}

// Walks the tagged fields of `data`, calling on_field(tag, value reader) for each; reports
// malformed fields and unknown ones (see record_format.hpp: tags 64..127 are skipped).
class Fields {
 public:
  Fields(std::span<const std::uint8_t> data, std::size_t base) : r_(data), base_(base) {}

  template <class Fn>
  bool each(const char* what, Fn&& on_field) {
    while (!r_.done()) {
      const std::size_t at = r_.position();
      std::uint64_t tag = 0;
      std::uint64_t length = 0;
      std::span<const std::uint8_t> value;
      if (!r_.varint(tag) || !r_.varint(length) || length > r_.left() || !r_.bytes(length, value)) {
        return fail(at, std::string(what) + ": a field runs past its end");
      }
      const int known = on_field(tag, value, base_ + at);
      if (known < 0) return false;  // on_field set the error
      if (known == 0 && !(tag >= 64 && tag < 128)) {
        return fail(at, std::string(what) + ": unknown field " + std::to_string(tag));
      }
    }
    return true;
  }
  bool fail(std::size_t at, std::string what) {
    what_ = std::move(what);
    offset_ = base_ + at;
    return false;
  }
  std::string what_;
  std::size_t offset_ = 0;

 private:
  ByteReader r_;
  std::size_t base_;
};

bool get_f64(std::span<const std::uint8_t> v, double& out) {
  ByteReader r(v);
  return v.size() == 8 && r.f64(out) && std::isfinite(out);
}

bool get_u64(std::span<const std::uint8_t> v, std::uint64_t& out) {
  ByteReader r(v);
  return v.size() == 8 && r.u64(out);
}

std::string text_of(std::span<const std::uint8_t> v) { return {reinterpret_cast<const char*>(v.data()), v.size()}; }

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
  for (const tool::ToolSpec& spec : h.tools) w.field(t(HeaderTag::kTool), encode_tool(spec));
  std::vector<std::uint8_t> entry;
  ByteWriter we(entry);
  for (int i = 0; i < 3; ++i) we.f64(h.entry.point_mm[i]);
  for (int i = 0; i < 3; ++i) we.f64(h.entry.direction[i]);
  w.field(t(HeaderTag::kEntry), entry);
  w.field_u64(t(HeaderTag::kHeldTool), h.held_tool);
  w.field_u64(t(HeaderTag::kHandKind), static_cast<std::uint64_t>(h.hand));
  w.field_text(t(HeaderTag::kHandDescription), h.hand_description);
  if (h.device) w.field(t(HeaderTag::kDevice), encode_device(*h.device));
  w.field_u64(t(HeaderTag::kPeriod_us), static_cast<std::uint64_t>(h.period_us));
  w.field_u64(t(HeaderTag::kHashEvery), static_cast<std::uint64_t>(h.hash_every));
  return out;
}

namespace {

// The error of a field with a bad value: its offset and what (empty: none yet).
struct FieldError {
  std::string what;
  std::size_t at = 0;
  int bad(std::size_t offset, std::string msg) {
    what = std::move(msg);
    at = offset;
    return -1;
  }
  // A nested walk that failed: its own error unless a field inside it already set one.
  int nested(const Fields& f) { return what.empty() ? bad(f.offset_, f.what_) : -1; }
};

// Which of the header's required fields were seen.
struct Seen {
  bool entry = false;
  bool held = false;
  bool hand = false;
};

int decode_section(bool next, std::span<const std::uint8_t> tv, std::size_t tat, tool::ToolSpec& spec, FieldError& err) {
  std::vector<tool::ToolSection>& list = next ? spec.next_coils : spec.sections;
  if (!next && list.size() >= tool::ToolLimits::kMaxSections) return err.bad(tat, "tool: more than 64 sections");
  if (next && list.size() >= tool::kMaxNextCoils) return err.bad(tat, "tool: more than 15 next coils");
  ByteReader r(tv);
  tool::ToolSection s;
  double shape = 0.0;
  if ((tv.size() != 40 && tv.size() != 56) || !r.f64(s.length_mm) || !r.f64(s.outer_diameter_mm) ||
      !r.f64(s.bending_stiffness_Nmm2) || !r.f64(s.torsion_stiffness_Nmm2) || !r.f64(s.curve_deg) ||
      (tv.size() == 56 && (!r.f64(shape) || !r.f64(s.loop_diameter_mm)))) {
    return err.bad(tat, "tool: a section is not 5 doubles (7 with a coil shape)");
  }
  if (shape != 0.0 && shape != 1.0 && shape != 2.0) return err.bad(tat, "tool: coil shape must be 1 or 2");
  s.shape = static_cast<tool::CoilShape>(static_cast<int>(shape));
  list.push_back(s);
  return 1;
}

int decode_balloon(std::span<const std::uint8_t> tv, std::size_t tat, tool::BalloonSpec& b, FieldError& err) {
  ByteReader r(tv);
  if (tv.size() < 48 || tv.size() % 16 != 0 || !r.f64(b.length_mm) || !r.f64(b.from_tip_mm) || !r.f64(b.nominal_atm) ||
      !r.f64(b.rated_burst_atm)) {
    return err.bad(tat, "tool: a balloon is not 4 doubles and (pressure, diameter) pairs");
  }
  for (std::size_t i = 32; i < tv.size(); i += 16) {
    double p = 0.0, dia = 0.0;
    if (!r.f64(p) || !r.f64(dia)) return err.bad(tat, "tool: a balloon is not 4 doubles and (pressure, diameter) pairs");
    b.pressure_atm.push_back(p);
    b.diameter_mm.push_back(dia);
  }
  return 1;
}

int decode_stent(std::span<const std::uint8_t> tv, std::size_t tat, tool::StentRetrieverSpec& st, FieldError& err) {
  ByteReader r(tv);
  if (tv.size() != 24 || !r.f64(st.diameter_mm) || !r.f64(st.length_mm) || !r.f64(st.embed_s)) {
    return err.bad(tat, "tool: a stent retriever is not 3 doubles");
  }
  return 1;
}

// A tool field holding one finite double: its slot in `spec`, or nullptr for another tag.
double* tool_double(std::uint64_t tt, tool::ToolSpec& spec) {
  using record::ToolTag;
  switch (static_cast<ToolTag>(tt)) {
    case ToolTag::kFriction: return &spec.friction;
    case ToolTag::kInnerDiameter: return &spec.inner_diameter_mm;
    case ToolTag::kAxialStiffness: return &spec.axial_stiffness_N;
    case ToolTag::kBloodViscosity: return &spec.blood_viscosity_mPa_s;
    case ToolTag::kMaxSpacing: return &spec.max_spacing_mm;
    case ToolTag::kTipSpacing: return &spec.tip_spacing_mm;
    case ToolTag::kTipZone: return &spec.tip_zone_mm;
    case ToolTag::kDetach: return &spec.detach_mm;
    default: return nullptr;
  }
}

int decode_tool_field(std::uint64_t tt, std::span<const std::uint8_t> tv, std::size_t tat, tool::ToolSpec& spec, FieldError& err) {
  using record::ToolTag;
  switch (static_cast<ToolTag>(tt)) {
    case ToolTag::kName: spec.name = text_of(tv); return 1;
    case ToolTag::kKind:
      if (tv.size() != 1 || tv[0] > 2) return err.bad(tat, "tool: kind must be 0, 1 or 2");
      spec.kind = static_cast<tool::ToolKind>(tv[0]);
      return 1;
    case ToolTag::kSection:
    case ToolTag::kNextCoil: return decode_section(tt == t(ToolTag::kNextCoil), tv, tat, spec, err);
    case ToolTag::kInside: spec.inside = text_of(tv); return 1;
    case ToolTag::kBalloon: return decode_balloon(tv, tat, spec.balloon, err);
    case ToolTag::kStentRetriever: return decode_stent(tv, tat, spec.stent, err);
    default: break;
  }
  double d = 0.0;
  if (tt == t(ToolTag::kDrag) || tt == t(ToolTag::kValveFriction)) {
    if (!get_f64(tv, d)) return err.bad(tat, "tool: field " + std::to_string(tt) + " is not a finite double");
    (tt == t(ToolTag::kDrag) ? spec.drag_mN_s_per_mm2 : spec.valve_friction_mN) = d;
    return 1;
  }
  double* target = tool_double(tt, spec);
  if (target == nullptr) return 0;
  if (!get_f64(tv, d)) return err.bad(tat, "tool: field " + std::to_string(tt) + " is not a finite double");
  *target = d;
  return 1;
}

int decode_tool(std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, FieldError& err) {
  if (h.tools.size() >= kMaxTools) return err.bad(at, "header: more than 4 tools");
  tool::ToolSpec spec;
  spec.sections.clear();
  Fields f(v, at);
  const bool ok = f.each("tool", [&](std::uint64_t tt, std::span<const std::uint8_t> tv, std::size_t tat) {
    return decode_tool_field(tt, tv, tat, spec, err);
  });
  if (!ok) return err.nested(f);
  h.tools.push_back(std::move(spec));
  return 1;
}

int decode_device_field(std::uint64_t dt, std::span<const std::uint8_t> dv, std::size_t dat, DeviceRecord& d, FieldError& err) {
  using record::DeviceTag;
  switch (static_cast<DeviceTag>(dt)) {
    case DeviceTag::kDescription: d.description = text_of(dv); return 1;
    case DeviceTag::kSerial: d.serial = text_of(dv); return 1;
    case DeviceTag::kBoard: d.board = text_of(dv); return 1;
    case DeviceTag::kFirmware: d.firmware = text_of(dv); return 1;
    default: break;
  }
  if (dt < t(DeviceTag::kInsertionCountsPerM) || dt > t(DeviceTag::kRotationActuator)) return 0;
  std::uint64_t n = 0;
  if (!get_u64(dv, n) || n > UINT32_MAX) return err.bad(dat, "device: field " + std::to_string(dt) + " out of range");
  const auto v32 = static_cast<std::uint32_t>(n);
  switch (static_cast<DeviceTag>(dt)) {
    case DeviceTag::kInsertionCountsPerM: d.insertion_counts_per_m = v32; break;
    case DeviceTag::kRotationCountsPerRev: d.rotation_counts_per_rev = v32; break;
    case DeviceTag::kInsertionFullScaleMn: d.insertion_full_scale_mN = v32; break;
    case DeviceTag::kRotationFullScaleUnm: d.rotation_full_scale_uNm = v32; break;
    case DeviceTag::kInsertionActuator: d.insertion_actuator = static_cast<std::uint8_t>(v32); break;
    default: d.rotation_actuator = static_cast<std::uint8_t>(v32); break;
  }
  return 1;
}

int decode_device(std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, FieldError& err) {
  DeviceRecord d;
  Fields f(v, at);
  const bool ok = f.each("device", [&](std::uint64_t dt, std::span<const std::uint8_t> dv, std::size_t dat) {
    return decode_device_field(dt, dv, dat, d, err);
  });
  if (!ok) return err.nested(f);
  h.device = std::move(d);
  return 1;
}

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
    case HeaderTag::kTool: return decode_tool(v, at, h, err);
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
    case HeaderTag::kDevice: return decode_device(v, at, h, err);
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
