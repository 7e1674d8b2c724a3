#include "tool/tool_spec.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::tool {
namespace {

bool in(double v, double lo, double hi) { return std::isfinite(v) && v >= lo && v <= hi; }
bool positive_up_to(double v, double hi) { return std::isfinite(v) && v > 0.0 && v <= hi; }

// The sections' values (`who` names the tool in the message).
std::string check_sections(const ToolSpec& t, const std::string& who) {
  using L = ToolLimits;
  for (const ToolSection& s : t.sections) {
    if (!positive_up_to(s.length_mm, L::kMaxLength_mm)) return who + "section length out of range";
    if (!positive_up_to(s.outer_diameter_mm, L::kMaxDiameter_mm)) return who + "od must be in (0, 20] mm";
    if (!positive_up_to(s.bending_stiffness_Nmm2, L::kMaxStiffness_Nmm2)) return who + "ei must be in (0, 1e6] N.mm2";
    if (!positive_up_to(s.torsion_stiffness_Nmm2, L::kMaxStiffness_Nmm2)) return who + "gj must be in (0, 1e6] N.mm2";
    if (!in(s.curve_deg, -L::kMaxCurve_deg, L::kMaxCurve_deg)) return who + "curve must be within +-360 degrees";
    if (s.shape != CoilShape::kNone && (t.kind != ToolKind::kCoil || !in(s.loop_diameter_mm, 2.0, 20.0))) {
      return who + "a coil shape needs a coil tool and a loop diameter in [2, 20] mm";
    }
  }
  return {};
}

// A coil's next coils: each one's values, then the tool carrying it checked whole.
std::string check_next_coils(const ToolSpec& t, const std::string& who) {
  using L = ToolLimits;
  if (t.next_coils.empty()) return {};
  if (t.kind != ToolKind::kCoil) return who + "next coils need a coil tool";
  if (t.next_coils.size() > kMaxNextCoils) return who + "at most 15 next coils";
  for (std::size_t k = 0; k < t.next_coils.size(); ++k) {
    const ToolSection& c = t.next_coils[k];
    if (!positive_up_to(c.length_mm, 300.0)) return who + "a next coil's length must be in (0, 300] mm";
    if (!positive_up_to(c.outer_diameter_mm, L::kMaxDiameter_mm)) return who + "a next coil's od must be in (0, 20] mm";
    if (!positive_up_to(c.bending_stiffness_Nmm2, L::kMaxStiffness_Nmm2) || !positive_up_to(c.torsion_stiffness_Nmm2, L::kMaxStiffness_Nmm2)) {
      return who + "a next coil's ei and gj must be in (0, 1e6] N.mm2";
    }
    if (c.shape == CoilShape::kNone || !in(c.loop_diameter_mm, 2.0, 20.0)) return who + "a next coil needs a shape and a loop diameter in [2, 20] mm";
    if (std::string e = check_tool(with_next_coil(t, k)); !e.empty()) return e;
  }
  return {};
}

}  // namespace

std::string check_tool(const ToolSpec& t) {
  using L = ToolLimits;
  const std::string who = "tool '" + t.name + "': ";
  if (t.name.empty()) return "a tool has no name";
  if (t.kind != ToolKind::kGuidewire && t.kind != ToolKind::kCatheter && t.kind != ToolKind::kCoil) return who + "unknown kind";
  if (t.sections.empty() || t.sections.size() > L::kMaxSections) return who + "needs 1 to 64 sections";
  if (std::string e = check_sections(t, who); !e.empty()) return e;
  if (t.kind == ToolKind::kCoil && !(t.detach_mm > 0.0 && t.detach_mm < t.length_mm())) return who + "a coil needs a detach length shorter than the tool";
  if (std::string e = check_next_coils(t, who); !e.empty()) return e;
  if (!in(t.friction, 0.0, L::kMaxFriction)) return who + "friction must be in [0, 2]";
  if (!in(t.inner_diameter_mm, 0.0, L::kMaxDiameter_mm)) return who + "inner_diameter must be in [0, 20] mm";
  if (!positive_up_to(t.max_spacing_mm, L::kMaxSpacing_mm)) return who + "node spacing must be in (0, 2] mm";
  if (!in(t.tip_spacing_mm, L::kMinTipSpacing_mm, t.max_spacing_mm)) return who + "tip spacing must be in [0.1, spacing] mm";
  if (!in(t.tip_zone_mm, 0.0, L::kMaxTipZone_mm)) return who + "tip zone must be in [0, 500] mm";
  if (t.drag_mN_s_per_mm2 && !in(*t.drag_mN_s_per_mm2, 0.0, L::kMaxDrag)) return who + "drag must be in [0, 10] mN.s/mm2";
  if (!in(t.blood_viscosity_mPa_s, L::kMinViscosity_mPa_s, L::kMaxViscosity_mPa_s)) return who + "blood viscosity must be in [0.5, 20] mPa.s";
  if (t.valve_friction_mN && !in(*t.valve_friction_mN, 0.0, L::kMaxValveFriction_mN)) return who + "valve_friction must be in [0, 2000] mN";
  if (!in(t.axial_stiffness_N, L::kMinAxialStiffness_N, L::kMaxAxialStiffness_N)) return who + "axial_stiffness must be in [10, 1e6] N";
  const double len = t.length_mm();
  if (t.balloon.present()) {
    if (std::string e = check_balloon(t.balloon, len); !e.empty()) return who + e;
  }
  if (t.stent.present()) {
    if (t.kind != ToolKind::kGuidewire) return who + "stent_retriever: only a push wire (a guidewire tool) carries one";
    if (std::string e = check_stent_retriever(t.stent, len); !e.empty()) return who + e;
  }
  if (len > L::kMaxLength_mm) return who + "longer than 4000 mm";
  if (len < 4.0 * t.max_spacing_mm) return who + "shorter than 4 node spacings";
  if (t.tip_zone_mm / t.tip_spacing_mm + len / t.max_spacing_mm > L::kMaxNodes) return who + "needs more than 6000 nodes";
  return {};
}


ToolSpec with_next_coil(const ToolSpec& spec, std::size_t next) {
  ToolSpec out = spec;
  out.next_coils.clear();
  if (next >= spec.next_coils.size()) return out;
  // The pusher: the sections less the first coil's distal detach_mm.
  double cut = spec.detach_mm;
  while (!out.sections.empty() && cut > 0.0) {
    ToolSection& last = out.sections.back();
    if (last.length_mm > cut + 1e-9) {
      last.length_mm -= cut;
      last.shape = CoilShape::kNone;
      last.loop_diameter_mm = 0.0;
      cut = 0.0;
    } else {
      cut -= last.length_mm;
      out.sections.pop_back();
    }
  }
  const ToolSection& coil = spec.next_coils[next];
  out.sections.push_back(coil);
  out.detach_mm = coil.length_mm;
  out.tip_zone_mm = std::max(0.0, spec.tip_zone_mm - spec.detach_mm) + coil.length_mm;
  return out;
}

std::string check_stent_retriever(const StentRetrieverSpec& s, double tool_length_mm) {
  if (!in(s.diameter_mm, 3.0, 6.0)) return "stent_retriever: diameter must be in [3, 6] mm";
  if (!in(s.length_mm, 20.0, 40.0)) return "stent_retriever: length must be in [20, 40] mm";
  if (s.length_mm >= tool_length_mm) return "stent_retriever: longer than its push wire";
  if (!positive_up_to(s.embed_s, 1800.0)) return "stent_retriever: embed must be in (0, 1800] s";
  return {};
}

std::string check_balloon(const BalloonSpec& b, double tool_length_mm) {
  constexpr double kMaxAtm = 30.0;
  if (!positive_up_to(b.length_mm, 100.0)) return "balloon: length must be in (0, 100] mm";
  if (!in(b.from_tip_mm, 0.0, 100.0)) return "balloon: from_tip must be in [0, 100] mm";
  if (b.from_tip_mm + b.length_mm > tool_length_mm) return "balloon: does not fit on the tool (from_tip + length > tool length)";
  if (!positive_up_to(b.nominal_atm, kMaxAtm)) return "balloon: nominal must be in (0, 30] atm";
  if (!in(b.rated_burst_atm, b.nominal_atm, kMaxAtm)) return "balloon: burst must be in [nominal, 30] atm";
  if (b.pressure_atm.empty() || b.pressure_atm.size() > 16 || b.pressure_atm.size() != b.diameter_mm.size()) {
    return "balloon: chart needs 1 to 16 PRESSURE:DIAMETER points";
  }
  for (std::size_t i = 0; i < b.pressure_atm.size(); ++i) {
    if (!positive_up_to(b.pressure_atm[i], kMaxAtm)) return "balloon: chart pressures must be in (0, 30] atm";
    if (!positive_up_to(b.diameter_mm[i], ToolLimits::kMaxDiameter_mm)) return "balloon: chart diameters must be in (0, 20] mm";
    if (i > 0 && b.pressure_atm[i] <= b.pressure_atm[i - 1]) return "balloon: chart pressures must increase";
    if (i > 0 && b.diameter_mm[i] < b.diameter_mm[i - 1]) return "balloon: chart diameters must not decrease";
  }
  return {};
}

double blood_drag_mN_s_per_mm2(double radius_mm, double viscosity_mPa_s, double lumen_radius_mm) {
  constexpr double kMilliPascalSecond = 1e-6;  // 1 mPa.s = 1e-3 N.s/m2 = 1e-6 mN.s/mm2
  // A tool nearly as wide as the lumen: the gap flow, capped at R/a = 1.5 (ln = 0.41).
  const double ratio = std::max(lumen_radius_mm / std::max(radius_mm, 1e-3), 1.5);
  return 2.0 * M_PI * viscosity_mPa_s * kMilliPascalSecond / std::log(ratio);
}

double ToolSpec::drag_at(double radius_mm) const {
  return drag_mN_s_per_mm2 ? *drag_mN_s_per_mm2 : blood_drag_mN_s_per_mm2(radius_mm, blood_viscosity_mPa_s);
}

double ToolSpec::valve_friction() const { return valve_friction_mN.value_or(kDefaultValveFriction_mN); }

bool nesting_cycle(std::span<const ToolSpec> tools, std::size_t i) {
  std::size_t at = i;
  for (std::size_t steps = 0; steps <= tools.size(); ++steps) {
    const std::string& outer = tools[at].inside;
    if (outer.empty()) return false;
    std::size_t next = tools.size();
    for (std::size_t j = 0; j < tools.size(); ++j) {
      if (tools[j].name == outer) next = j;
    }
    if (next == tools.size()) return false;  // an unknown name is reported on its own
    if (next == i) return true;
    at = next;
  }
  return true;
}

std::string check_tools(std::span<const ToolSpec> tools) {
  if (tools.empty() || tools.size() > ToolLimits::kMaxTools) return "a case has 1 to " + std::to_string(ToolLimits::kMaxTools) + " tools";
  for (const ToolSpec& t : tools) {
    if (std::string e = check_tool(t); !e.empty()) return e;
  }
  for (std::size_t i = 0; i < tools.size(); ++i) {
    for (std::size_t j = 0; j < i; ++j) {
      if (tools[i].name == tools[j].name) return "tool '" + tools[i].name + "' defined twice";
    }
    const ToolSpec& t = tools[i];
    if (t.stent.present() && t.inside.empty()) return "tool '" + t.name + "': a stent retriever runs inside the catheter that delivers it";
    if (t.inside.empty()) continue;
    const ToolSpec* outer = nullptr;
    for (const ToolSpec& o : tools) if (o.name == t.inside) outer = &o;
    if (outer == nullptr) return "tool '" + t.name + "': inside unknown tool '" + t.inside + "'";
    if (outer == &t) return "tool '" + t.name + "' cannot be inside itself";
    if (nesting_cycle(tools, i)) return "tool '" + t.name + "': the tools it runs in run inside it";
    const double od = t.max_outer_diameter_mm();
    if (outer->inner_diameter_mm <= od) return "tool '" + t.name + "' does not fit in '" + outer->name + "'";
  }
  return {};
}

}  // namespace cathbox::tool
