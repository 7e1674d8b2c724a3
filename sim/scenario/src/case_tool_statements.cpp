// The case file's tool statements: `tool NAME KIND` and the lines up to its `end` (sections,
// coils, balloon, stent retriever, aspiration), each tool checked at its `end`, the tools' nesting
// after the last line.
#include "case_parser.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace cathbox::tool::detail {

// `tool NAME KIND`: a new tool, whose lines follow up to its `end`.
bool CaseParser::tool_header(const std::vector<std::string_view>& w) {
  if (!expect_args(w, 2)) return false;
  if (c_.tools.size() >= kMaxTools) return error_here("too many tools (at most " + std::to_string(kMaxTools) + ")");
  for (const ToolSpec& t : c_.tools) {
    if (t.name == w[1]) return error_here("tool '" + std::string(w[1]) + "' defined twice");
  }
  ToolSpec spec;
  spec.sections.clear();
  spec.name = std::string(w[1]);
  if (w[2] == "guidewire") {
    spec.kind = ToolKind::kGuidewire;
  } else if (w[2] == "catheter") {
    spec.kind = ToolKind::kCatheter;
  } else if (w[2] == "coil") {
    spec.kind = ToolKind::kCoil;
  } else {
    return error_here("tool: kind must be 'guidewire', 'catheter' or 'coil', not '" + std::string(w[2]) + "'");
  }
  c_.tools.push_back(spec);
  tool_ = &c_.tools.back();
  tool_line_ = lines_.line();
  tool_lines_.push_back(tool_line_);
  return true;
}

bool CaseParser::tool_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
  const std::string_view key = w[0];
  double v = 0.0;
  if (key == "section") return section_statement(t, w);
  if (key == "next_coil") return next_coil_statement(t, w);
  if (key == "friction") return bounded_value(w, 0.0, 2.0, "friction must be in [0, 2]", t.friction);
  if (key == "inner_diameter") return bounded_value(w, 0.0, 20.0, "inner_diameter must be in [0, 20] mm", t.inner_diameter_mm);
  if (key == "inside") {
    if (!expect_args(w, 1)) return false;
    t.inside = std::string(w[1]);
    return true;
  }
  if (key == "spacing") return spacing_statement(t, w);
  if (key == "drag") {
    if (!bounded_value(w, 0.0, 10.0, "drag must be in [0, 10] mN.s/mm2", v)) return false;
    t.drag_mN_s_per_mm2 = v;
    return true;
  }
  if (key == "valve_friction") {
    if (!bounded_value(w, 0.0, ToolLimits::kMaxValveFriction_mN, "valve_friction must be in [0, 2000] mN", v)) return false;
    t.valve_friction_mN = v;
    return true;
  }
  if (key == "detach") {
    if (!expect_args(w, 1) || !number(w[1], "detach", v)) return false;
    if (t.kind != ToolKind::kCoil) return error_here("detach is for coil tools");
    if (v <= 0.0 || v > 300.0) return error_here("detach: coil length must be in (0, 300] mm");
    t.detach_mm = v;
    return true;
  }
  if (key == "balloon") return balloon_statement(t, w);
  if (key == "stent_retriever") return stent_statement(t, w);
  if (key == "axial_stiffness") return bounded_value(w, 10.0, 1e6, "axial_stiffness must be in [10, 1e6] N", t.axial_stiffness_N);
  return error_here("unknown tool keyword '" + std::string(key) + "'");
}

// `KEY VALUE` with VALUE in [lo, hi]: into `out`, else `message`.
bool CaseParser::bounded_value(const std::vector<std::string_view>& w, double lo, double hi, const char* message, double& out) {
  double v = 0.0;
  if (!expect_args(w, 1) || !number(w[1], std::string(w[0]), v)) return false;
  if (v < lo || v > hi) return error_here(message);
  out = v;
  return true;
}

bool CaseParser::section_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
  if (t.sections.size() >= kMaxSections) return error_here("too many sections (at most 64)");
  ToolSection s;
  if (!section_words(w, t.kind, s)) return false;
  t.sections.push_back(s);
  return true;
}

bool CaseParser::next_coil_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
  if (t.kind != ToolKind::kCoil) return error_here("next_coil is for coil tools");
  if (t.next_coils.size() >= kMaxNextCoils) return error_here("too many next coils (at most 15)");
  ToolSection s;
  if (!section_words(w, t.kind, s)) return false;
  if (s.length_mm > 300.0) return error_here("next_coil: coil length must be in (0, 300] mm");
  if (s.shape == CoilShape::kNone) return error_here("next_coil: shape= and loop= are required");
  t.next_coils.push_back(s);
  return true;
}

// `spacing MAX_MM TIP_MM [TIP_ZONE_MM]`.
bool CaseParser::spacing_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
  if (w.size() != 3 && w.size() != 4) return error_here("spacing: expected MAX_MM TIP_MM [TIP_ZONE_MM]");
  double mx = 0.0, tip = 0.0, zone = t.tip_zone_mm;
  if (!number(w[1], "spacing", mx) || !number(w[2], "tip spacing", tip)) return false;
  if (w.size() == 4 && !number(w[3], "tip zone", zone)) return false;
  if (mx <= 0.0 || mx > 2.0) return error_here("spacing: node spacing must be in (0, 2] mm");
  if (tip < 0.1 || tip > mx) return error_here("spacing: tip spacing must be in [0.1, spacing] mm");
  if (zone < 0.0 || zone > 500.0) return error_here("spacing: tip zone must be in [0, 500] mm");
  t.max_spacing_mm = mx;
  t.tip_spacing_mm = tip;
  t.tip_zone_mm = zone;
  return true;
}

// `section` and `next_coil`: LENGTH od=MM ei=N.mm2 gj=N.mm2 [curve=DEG] [shape=... loop=MM].
bool CaseParser::section_words(const std::vector<std::string_view>& w, ToolKind kind, ToolSection& s) {
  const std::string verb(w[0]);
  if (w.size() < 2) return error_here(verb + ": missing length");
  double len = 0.0;
  if (!number(w[1], verb + " length", len)) return false;
  if (len <= 0.0) return error_here(verb + ": length must be > 0");
  s.length_mm = len;
  SectionKeys given;
  for (std::size_t i = 2; i < w.size(); ++i) {
    const std::size_t eq = w[i].find('=');
    if (eq == std::string_view::npos) return error_here(verb + ": expected key=value, got '" + std::string(w[i]) + "'");
    if (!section_key(verb, w[i].substr(0, eq), w[i].substr(eq + 1), s, given)) return false;
  }
  if (!given.od || !given.ei || !given.gj) return error_here(verb + ": od=, ei= and gj= are required");
  if ((s.shape != CoilShape::kNone) != (s.loop_diameter_mm > 0.0)) return error_here(verb + ": shape= and loop= go together");
  if (s.shape != CoilShape::kNone && kind != ToolKind::kCoil) return error_here(verb + ": shape= is for coil tools");
  return true;
}

// One KEY=VALUE of a section.
bool CaseParser::section_key(const std::string& verb, std::string_view k, std::string_view value, ToolSection& s, SectionKeys& given) {
  if (k == "shape") {
    if (value == "helix") {
      s.shape = CoilShape::kHelix;
    } else if (value == "complex") {
      s.shape = CoilShape::kComplex;
    } else {
      return error_here(verb + ": shape must be 'helix' or 'complex', not '" + std::string(value) + "'");
    }
    return true;
  }
  double v = 0.0;
  if (!number(value, std::string(k), v)) return false;
  if (k == "loop") {
    if (v < 2.0 || v > 20.0) return error_here(verb + ": loop diameter must be in [2, 20] mm");
    s.loop_diameter_mm = v;
  } else if (k == "od") {
    if (v <= 0.0 || v > 20.0) return error_here(verb + ": od must be in (0, 20] mm");
    s.outer_diameter_mm = v;
    given.od = true;
  } else if (k == "ei") {
    if (v <= 0.0 || v > 1e6) return error_here(verb + ": ei must be in (0, 1e6] N.mm2");
    s.bending_stiffness_Nmm2 = v;
    given.ei = true;
  } else if (k == "gj") {
    if (v <= 0.0 || v > 1e6) return error_here(verb + ": gj must be in (0, 1e6] N.mm2");
    s.torsion_stiffness_Nmm2 = v;
    given.gj = true;
  } else if (k == "curve") {
    if (std::abs(v) > 360.0) return error_here(verb + ": curve must be within +-360 degrees");
    s.curve_deg = v;
  } else {
    return error_here(verb + ": unknown key '" + std::string(k) + "' (known: od ei gj curve shape loop)");
  }
  return true;
}

// `aspiration pump|syringe` in a catheter with a lumen.
bool CaseParser::aspiration_statement(Case& c, const ToolSpec& t, const std::vector<std::string_view>& w) {
  if (!expect_args(w, 1)) return false;
  if (t.kind != ToolKind::kCatheter) return error_here("aspiration: only a catheter aspirates");
  for (const CaseAspiration& a : c.aspiration) {
    if (a.tool == t.name) return error_here("aspiration given twice");
  }
  CaseAspiration a{t.name, flow::VacuumSource::kPump, lines_.line()};
  if (w[1] == "syringe") {
    a.source = flow::VacuumSource::kSyringe60;
  } else if (w[1] != "pump") {
    return error_here("aspiration: source must be 'pump' or 'syringe', not '" + std::string(w[1]) + "'");
  }
  c.aspiration.push_back(a);
  return true;
}

// `balloon length=MM from_tip=MM nominal=ATM burst=ATM chart=P:D,P:D,...` on a catheter.
bool CaseParser::balloon_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
  if (t.kind != ToolKind::kCatheter) return error_here("balloon: only a catheter carries a balloon");
  if (t.balloon.present()) return error_here("balloon given twice");
  BalloonSpec b;
  bool length = false, chart = false;
  for (std::size_t i = 1; i < w.size(); ++i) {
    const std::size_t eq = w[i].find('=');
    if (eq == std::string_view::npos) return error_here("balloon: expected key=value, got '" + std::string(w[i]) + "'");
    const std::string_view k = w[i].substr(0, eq);
    const std::string_view value = w[i].substr(eq + 1);
    if (k == "chart") {
      chart = true;
      for (std::size_t at = 0; at <= value.size();) {
        const std::size_t comma = std::min(value.find(',', at), value.size());
        const std::string_view point = value.substr(at, comma - at);
        const std::size_t colon = point.find(':');
        if (colon == std::string_view::npos) return error_here("balloon: chart point '" + std::string(point) + "' is not PRESSURE:DIAMETER");
        double p = 0.0, d = 0.0;
        if (!number(point.substr(0, colon), "balloon chart pressure", p) || !number(point.substr(colon + 1), "balloon chart diameter", d)) return false;
        b.pressure_atm.push_back(p);
        b.diameter_mm.push_back(d);
        at = comma + 1;
      }
      continue;
    }
    double v = 0.0;
    if (!number(value, "balloon " + std::string(k), v)) return false;
    if (k == "length") {
      b.length_mm = v;
      length = true;
    } else if (k == "from_tip") {
      b.from_tip_mm = v;
    } else if (k == "nominal") {
      b.nominal_atm = v;
    } else if (k == "burst") {
      b.rated_burst_atm = v;
    } else {
      return error_here("balloon: unknown key '" + std::string(k) + "' (known: length from_tip nominal burst chart)");
    }
  }
  if (!length || !chart) return error_here("balloon: length= and chart= are required");
  if (std::string e = check_balloon(b, t.length_mm()); !e.empty()) return error_here(e);
  t.balloon = b;
  return true;
}

// `stent_retriever diameter=MM length=MM [embed=S]` on a push wire (a guidewire tool).
bool CaseParser::stent_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
  if (t.kind != ToolKind::kGuidewire) return error_here("stent_retriever: only a push wire (a guidewire tool) carries one");
  if (t.stent.present()) return error_here("stent_retriever given twice");
  StentRetrieverSpec st;
  bool diameter = false, length = false;
  const bool pairs = number_pairs(w, 1, "stent_retriever", [&](std::string_view k, double v) {
    if (k == "diameter") {
      st.diameter_mm = v;
      diameter = true;
    } else if (k == "length") {
      st.length_mm = v;
      length = true;
    } else if (k == "embed") {
      st.embed_s = v;
    } else {
      return error_here("stent_retriever: unknown key '" + std::string(k) + "' (known: diameter length embed)");
    }
    return true;
  });
  if (!pairs) return false;
  if (!diameter || !length) return error_here("stent_retriever: diameter= and length= are required");
  if (std::string e = check_stent_retriever(st, std::numeric_limits<double>::infinity()); !e.empty()) return error_here(e);
  t.stent = st;
  stent_line_ = lines_.line();
  return true;
}

bool CaseParser::check_tool(const ToolSpec& t, std::size_t line) {
  const double len = t.length_mm();
  if (len > kMaxToolLength_mm) return error_at(line, "tool '" + t.name + "' is longer than 4000 mm");
  if (len < 4.0 * t.max_spacing_mm) return error_at(line, "tool '" + t.name + "' is shorter than 4 node spacings");
  const double nodes = t.tip_zone_mm / t.tip_spacing_mm + len / t.max_spacing_mm;
  if (nodes > kMaxNodes) return error_at(line, "tool '" + t.name + "' needs more than 6000 nodes");
  if (t.stent.present() && t.stent.length_mm >= len) return error_at(stent_line_, "stent_retriever: longer than its push wire '" + t.name + "'");
  if (t.stent.present() && t.inside.empty()) {
    return error_at(stent_line_, "stent_retriever: the push wire '" + t.name + "' must run inside the catheter that delivers it (inside NAME)");
  }
  if (t.kind == ToolKind::kCoil && !(t.detach_mm > 0.0 && t.detach_mm < len)) {
    return error_at(line, "coil '" + t.name + "' needs 'detach MM' shorter than the tool");
  }
  for (std::size_t k = 0; k < t.next_coils.size(); ++k) {
    // As a record's reader will check it: the tool each next coil makes once loaded.
    if (std::string e = tool::check_tool(with_next_coil(t, k)); !e.empty()) {
      return error_at(line, "with its next coil " + std::to_string(k + 1) + ": " + e);
    }
  }
  return true;
}

// Every `inside NAME`: a known catheter other than the tool, no cycle, and room for the tool.
bool CaseParser::check_coaxial() {
  for (std::size_t i = 0; i < c_.tools.size(); ++i) {
    const ToolSpec& t = c_.tools[i];
    if (t.inside.empty()) continue;
    const ToolSpec* outer = nullptr;
    for (const ToolSpec& o : c_.tools) if (o.name == t.inside) outer = &o;
    const std::size_t line = tool_lines_[i];
    if (outer == nullptr) return error_at(line, "tool '" + t.name + "': inside unknown tool '" + t.inside + "'");
    if (outer == &t) return error_at(line, "tool '" + t.name + "' cannot be inside itself");
    if (nesting_cycle(c_.tools, i)) return error_at(line, "tool '" + t.name + "': the tools it runs in run inside it");
    if (outer->kind != ToolKind::kCatheter) return error_at(line, "tool '" + t.name + "': '" + outer->name + "' is not a catheter");
    const double od = t.max_outer_diameter_mm();
    if (outer->inner_diameter_mm <= od) {
      return error_at(line, "tool '" + t.name + "' (od " + std::to_string(od) + " mm) does not fit in '" + outer->name + "'");
    }
  }
  return true;
}

}  // namespace cathbox::tool::detail
