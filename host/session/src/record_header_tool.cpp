#include "record_header_tool.hpp"

namespace cathbox::session::record {
namespace {

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

}  // namespace

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

int decode_tool(std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, FieldError& err) {
  if (h.tools.size() >= kMaxTools) return err.bad(at, "header: more than " + std::to_string(kMaxTools) + " tools");
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

}  // namespace cathbox::session::record
