#include "scenario/case_file.hpp"

#include <cmath>
#include <filesystem>
#include <limits>
#include <utility>

#include <glm/geometric.hpp>

#include "tool/aneurysm_sac.hpp"
#include "base/read_file.hpp"
#include "base/text_lines.hpp"

namespace cathbox::tool {

using base::text::TextLines;
using base::text::located;
using base::text::parse_number;

namespace {

constexpr std::size_t kMaxCaseBytes = 16u << 20;
constexpr std::size_t kMaxTools = ToolLimits::kMaxTools;
constexpr std::size_t kMaxTubes = 200000;
constexpr std::size_t kMaxSections = ToolLimits::kMaxSections;
constexpr double kMaxToolLength_mm = ToolLimits::kMaxLength_mm;
constexpr double kMaxNodes = ToolLimits::kMaxNodes;
constexpr std::size_t kMaxFlowSettings = 100000;
constexpr std::size_t kMaxViews = 16;
constexpr std::size_t kMaxClots = 16;

class CaseParser {
 public:
  CaseParser(std::string_view text, std::string_view file) : lines_(text), file_(file) {}

  CaseParse run() {
    std::vector<std::string_view> w;
    while (lines_.next(w)) {
      if (!(tool_ != nullptr ? in_tool_statement(w) : statement(w))) return fail();
    }
    if (tool_ != nullptr) return fail_at(tool_line_, "tool '" + tool_->name + "' has no 'end'");
    if (!check_vessel() || !check_coaxial() || !check_aspiration()) return fail();
    if (c_.tools.empty()) c_.tools.push_back(default_guidewire());
    // One blood and one sheath for the whole case: the tools' drag follows the flow model's
    // viscosity; the case's valve friction is the default of every tool that gives none.
    for (ToolSpec& t : c_.tools) {
      t.blood_viscosity_mPa_s = c_.flow.viscosity_mPa_s;
      if (!t.valve_friction_mN && c_.valve_friction_mN) t.valve_friction_mN = c_.valve_friction_mN;
    }
    c_.flow.source = std::string(file_);
    return std::move(c_);
  }

 private:
  // Which once-only keywords were given.
  struct Seen {
    bool header = false, name = false, entry = false, target = false, realistic = false, valve = false, threshold = false,
         aneurysm = false, wall = false;
  };

  // A line between `tool NAME KIND` and its `end`.
  bool in_tool_statement(const std::vector<std::string_view>& w) {
    const std::string_view key = w[0];
    if (key == "end") {
      if (!expect_args(w, 0)) return false;
      if (tool_->sections.empty()) return error_at(tool_line_, "tool '" + tool_->name + "' has no section");
      if (!check_tool(*tool_, tool_line_)) return false;
      tool_ = nullptr;
      return true;
    }
    if (key == "aspiration") return aspiration_statement(c_, *tool_, w);
    return tool_statement(*tool_, w);
  }

  // A line outside a tool: its keyword's statement.
  bool statement(const std::vector<std::string_view>& w) {
    using Handler = bool (CaseParser::*)(const std::vector<std::string_view>&);
    static constexpr std::pair<std::string_view, Handler> kStatements[] = {
        {"cathbox-case", &CaseParser::header_statement},
        {"name", &CaseParser::name_statement},
        {"vessel", &CaseParser::path_statement},
        {"surface", &CaseParser::path_statement},
        {"tube", &CaseParser::tube_statement},
        {"entry", &CaseParser::entry_statement},
        {"target", &CaseParser::target_statement},
        {"wall_force_threshold", &CaseParser::threshold_statement},
        {"tool", &CaseParser::tool_header},
        {"aneurysm", &CaseParser::aneurysm_statement},
        {"view", &CaseParser::view_statement},
        {"valve_friction", &CaseParser::valve_statement},
        {"wall", &CaseParser::wall_statement},
        {"realistic", &CaseParser::realistic_statement},
        {"flow", &CaseParser::case_flow_statement},
        {"clot", &CaseParser::case_clot_statement},
    };
    for (const auto& [keyword, handler] : kStatements) {
      if (w[0] == keyword) return (this->*handler)(w);
    }
    if (w[0] == "end") return error_here("'end' without a tool");
    return error_here("unknown keyword '" + std::string(w[0]) + "'");
  }

  bool header_statement(const std::vector<std::string_view>& w) {
    if (!expect_args(w, 1) || !once(seen_.header, w[0])) return false;
    if (w[1] != "1") return error_here("unsupported case version '" + std::string(w[1]) + "' (known: 1)");
    return true;
  }

  bool name_statement(const std::vector<std::string_view>& w) {
    if (w.size() < 2) return error_here("name: missing value");
    if (!once(seen_.name, w[0])) return false;
    c_.name = std::string(w[1]);
    for (std::size_t i = 2; i < w.size(); ++i) c_.name += " " + std::string(w[i]);
    return true;
  }

  bool threshold_statement(const std::vector<std::string_view>& w) {
    double v[1];
    if (!expect_args(w, 1) || !once(seen_.threshold, w[0]) || !numbers(w, 1, v, 1)) return false;
    if (!(v[0] > 0.0) || v[0] > 1e6) return error_here("wall_force_threshold: mN must be in (0, 1e6]");
    c_.wall_force_threshold_mN = v[0];
    return true;
  }

  bool valve_statement(const std::vector<std::string_view>& w) {
    double v[1];
    if (!expect_args(w, 1) || !once(seen_.valve, w[0]) || !numbers(w, 1, v, 1)) return false;
    if (v[0] < 0.0 || v[0] > ToolLimits::kMaxValveFriction_mN) return error_here("valve_friction must be in [0, 2000] mN");
    c_.valve_friction_mN = v[0];
    return true;
  }

  bool realistic_statement(const std::vector<std::string_view>& w) {
    if (!expect_args(w, 0) || !once(seen_.realistic, w[0])) return false;
    c_.realistic = true;
    return true;
  }

  bool case_flow_statement(const std::vector<std::string_view>& w) { return flow_statement(c_.flow, w); }
  bool case_clot_statement(const std::vector<std::string_view>& w) { return clot_statement(c_, w); }

  // `vessel FILE` or `surface FILE`: the path relative to the case file's folder.
  bool path_statement(const std::vector<std::string_view>& w) {
    if (!expect_args(w, 1)) return false;
    std::string& path = w[0] == "vessel" ? c_.vessel_path : c_.surface_path;
    if (!path.empty()) return error_here(std::string(w[0]) + " given twice");
    std::filesystem::path p{std::string(w[1])};
    if (p.is_relative()) p = std::filesystem::path{std::string(file_)}.parent_path() / p;
    path = p.lexically_normal().string();
    return true;
  }

  bool tube_statement(const std::vector<std::string_view>& w) {
    double v[9];
    if (!expect_args(w, 9) || !numbers(w, 1, v, 9)) return false;
    if (c_.tubes.size() >= kMaxTubes) return error_here("too many tubes (at most 200000)");
    if (v[0] != std::floor(v[0]) || std::abs(v[0]) > 2e9) return error_here("tube: segment id must be an integer");
    if (v[4] <= 0.0 || v[8] <= 0.0) return error_here("tube: radius must be > 0");
    c_.tubes.push_back(Tube{{v[1], v[2], v[3]}, {v[5], v[6], v[7]}, v[4], v[8], static_cast<std::int32_t>(v[0])});
    return true;
  }

  bool entry_statement(const std::vector<std::string_view>& w) {
    double v[6];
    if (!expect_args(w, 6) || !once(seen_.entry, w[0]) || !numbers(w, 1, v, 6)) return false;
    const glm::dvec3 d(v[3], v[4], v[5]);
    const double len = glm::length(d);
    if (!(len > 1e-9) || !std::isfinite(len)) return error_here("entry: direction must not be zero");
    c_.entry = Entry{{v[0], v[1], v[2]}, d / len};
    return true;
  }

  bool target_statement(const std::vector<std::string_view>& w) {
    double v[2];
    if (!expect_args(w, 2) || !once(seen_.target, w[0]) || !numbers(w, 1, v, 2)) return false;
    if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 2e9) return error_here("target: segment id must be an integer >= 0");
    if (v[1] < 0.0 || v[1] > 1.0) return error_here("target: fraction must be in [0, 1]");
    c_.target = CaseTarget{static_cast<std::int32_t>(v[0]), v[1]};
    return true;
  }

  // `tool NAME KIND`: a new tool, whose lines follow up to its `end`.
  bool tool_header(const std::vector<std::string_view>& w) {
    if (!expect_args(w, 2)) return false;
    if (c_.tools.size() >= kMaxTools) return error_here("too many tools (at most 4)");
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

  bool aneurysm_statement(const std::vector<std::string_view>& w) {
    double v[7];
    if (!expect_args(w, 7) || !once(seen_.aneurysm, w[0]) || !numbers(w, 1, v, 7)) return false;
    if (v[3] < 1.0 || v[3] > 15.0) return error_here("aneurysm: dome radius must be in [1, 15] mm");
    c_.aneurysm = sphere_cap_sac({v[0], v[1], v[2]}, v[3], {v[4], v[5], v[6]});
    if (!c_.aneurysm) return error_here("aneurysm: the neck centre must lie inside the dome sphere, off its centre");
    return true;
  }

  bool view_statement(const std::vector<std::string_view>& w) {
    double v[2];
    if (!expect_args(w, 3) || !numbers(w, 2, v, 2)) return false;
    if (c_.views.size() >= kMaxViews) return error_here("too many views (at most 16)");
    for (const flow::NamedProjection& other : c_.views) {
      if (other.name == w[1]) return error_here("view '" + std::string(w[1]) + "' defined twice");
    }
    if (std::abs(v[0]) > 120.0) return error_here("view: LAO/RAO angle must be within +-120 degrees");
    if (std::abs(v[1]) > 60.0) return error_here("view: cranial/caudal angle must be within +-60 degrees");
    c_.views.push_back(flow::NamedProjection{std::string(w[1]), v[0], v[1]});
    return true;
  }

  bool wall_statement(const std::vector<std::string_view>& w) {
    double v[1];
    if (!expect_args(w, 2) || !once(seen_.wall, w[0]) || !numbers(w, 2, v, 1)) return false;
    CaseWall cw;
    if (w[1] == "cervical") {
      cw.territory = Territory::kCervical;
    } else if (w[1] == "intracranial") {
      cw.territory = Territory::kIntracranial;
    } else {
      return error_here("wall: territory must be 'cervical' or 'intracranial', not '" + std::string(w[1]) + "'");
    }
    if (v[0] < 0.5 || v[0] > 15.0) return error_here("wall: lumen radius must be in [0.5, 15] mm");
    cw.radius_mm = v[0];
    c_.wall = cw;
    return true;
  }

  // After the last line: a vessel in one form, and what a surface needs.
  bool check_vessel() {
    const std::size_t last = lines_.line();
    if (c_.vessel_path.empty() && c_.tubes.empty()) return error_at(last, "no vessel: give 'vessel FILE' or 'tube' lines");
    if (!c_.vessel_path.empty() && !c_.tubes.empty()) return error_at(last, "give either 'vessel' or 'tube' lines, not both");
    if (!c_.surface_path.empty() && c_.vessel_path.empty()) {
      return error_at(last, "a 'surface' needs a 'vessel' (its centreline graph: route, targets, flow)");
    }
    if (!c_.surface_path.empty() && c_.wall) {
      return error_at(last, "a compliant 'wall' is re-meshed from the vessel's centrelines: it cannot take a 'surface'");
    }
    if (c_.tubes.size() > 0 && !c_.entry) return error_at(last, "analytic tubes need an 'entry'");
    return true;
  }

  // Every `inside NAME`: a known catheter other than the tool, no cycle, and room for the tool.
  bool check_coaxial() {
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

  bool check_aspiration() {
    for (const CaseAspiration& a : c_.aspiration) {
      for (const ToolSpec& t : c_.tools) {
        if (t.name == a.tool && !(t.inner_diameter_mm > 0.0)) return error_at(a.line, "aspiration: tool '" + t.name + "' has no inner_diameter");
      }
    }
    return true;
  }

  bool tool_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
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
  bool bounded_value(const std::vector<std::string_view>& w, double lo, double hi, const char* message, double& out) {
    double v = 0.0;
    if (!expect_args(w, 1) || !number(w[1], std::string(w[0]), v)) return false;
    if (v < lo || v > hi) return error_here(message);
    out = v;
    return true;
  }

  bool section_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
    if (t.sections.size() >= kMaxSections) return error_here("too many sections (at most 64)");
    ToolSection s;
    if (!section_words(w, t.kind, s)) return false;
    t.sections.push_back(s);
    return true;
  }

  bool next_coil_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
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
  bool spacing_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
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

  // Which of a section's required keys were given.
  struct SectionKeys {
    bool od = false, ei = false, gj = false;
  };

  // `section` and `next_coil`: LENGTH od=MM ei=N.mm2 gj=N.mm2 [curve=DEG] [shape=... loop=MM].
  bool section_words(const std::vector<std::string_view>& w, ToolKind kind, ToolSection& s) {
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
  bool section_key(const std::string& verb, std::string_view k, std::string_view value, ToolSection& s, SectionKeys& given) {
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

  // `clot SEG FROM_MM LENGTH_MM [red=PCT] [fibrin=PCT] [open=F]`.
  bool clot_statement(Case& c, const std::vector<std::string_view>& w) {
    if (w.size() < 4) return error_here("clot: expected SEG FROM_MM LENGTH_MM [red=PCT] [fibrin=PCT] [open=F]");
    if (c.clots.size() >= kMaxClots) return error_here("too many clots (at most 16)");
    double v[3];
    if (!numbers(w, 1, v, 3)) return false;
    if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 2e9) return error_here("clot: segment id must be an integer >= 0");
    if (v[1] < 0.0 || v[1] > 1000.0) return error_here("clot: start must be in [0, 1000] mm along the segment");
    if (v[2] <= 0.0 || v[2] > 100.0) return error_here("clot: length must be in (0, 100] mm");
    CaseClot clot{static_cast<std::int32_t>(v[0]), v[1], v[2], flow::kReferenceComposition, 0.0, lines_.line()};
    const bool pairs = number_pairs(w, 4, "clot", [&](std::string_view k, double x) {
      if (k == "red") {
        clot.composition.red_cell_percent = x;
      } else if (k == "fibrin") {
        clot.composition.fibrin_platelet_percent = x;
      } else if (k == "open") {
        if (x < 0.0 || x >= 1.0) return error_here("clot: open must be in [0, 1)");
        clot.open_fraction = x;
      } else {
        return error_here("clot: unknown key '" + std::string(k) + "' (known: red fibrin open)");
      }
      return true;
    });
    if (!pairs) return false;
    if (const char* e = flow::check_composition(clot.composition); *e != '\0') return error_here(e);
    c.clots.push_back(clot);
    return true;
  }

  // `aspiration pump|syringe` in a catheter with a lumen.
  bool aspiration_statement(Case& c, const ToolSpec& t, const std::vector<std::string_view>& w) {
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
  bool balloon_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
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
  bool stent_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
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

  // `flow KEY VALUES...`: the blood-flow model's settings (sim/flow/README.md). Segment ids are
  // checked against the vessel model when the flow network is built, naming this line.
  bool flow_statement(flow::FlowSettings& f, const std::vector<std::string_view>& w) {
    if (w.size() < 2) return error_here("flow: missing setting (viscosity cardiac_output cerebral_fraction pressure "
                                        "wall_shear_stress dispersion pulsatile terminals inflow outlet closed)");
    const std::string_view key = w[1];
    if (key == "viscosity") return flow_scalar(w, f.viscosity_mPa_s, 0.5, 20.0, false, "[0.5, 20] mPa.s");
    if (key == "cardiac_output") return flow_scalar(w, f.cardiac_output_ml_min, 500.0, 40000.0, false, "[500, 40000] mL/min");
    if (key == "cerebral_fraction") return flow_scalar(w, f.cerebral_fraction, 0.0, 0.5, true, "(0, 0.5]");
    if (key == "wall_shear_stress") return flow_scalar(w, f.wall_shear_stress_Pa, 0.0, 20.0, true, "(0, 20] Pa");
    if (key == "dispersion") return flow_scalar(w, f.dispersion_radii, 0.0, 20.0, false, "[0, 20] radii");
    if (key == "pressure") {
      if (!flow_args(w, 2, 2) || !once_flow(key) || !flow_value_in(w, 2, 20.0, 250.0, false, "[20, 250] mmHg", f.arterial_pressure_mmHg) ||
          !flow_value_in(w, 3, 0.0, 50.0, false, "[0, 50] mmHg", f.venous_pressure_mmHg)) {
        return false;
      }
      if (f.venous_pressure_mmHg >= f.arterial_pressure_mmHg) return error_here("flow pressure: venous must be below arterial pressure");
      return true;
    }
    if (key == "pulsatile") {
      return flow_args(w, 2, 2) && once_flow(key) && flow_value_in(w, 2, 0.0, 300.0, true, "(0, 300] bpm", f.heart_rate_bpm) &&
             flow_value_in(w, 3, 0.0, 2.0, false, "[0, 2]", f.pulsatility_index);
    }
    if (key == "terminals") {
      if (!flow_args(w, 1, 1) || !once_flow(key)) return false;
      if (w[2] != "calibrated" && w[2] != "fixed") {
        return error_here("flow terminals: expected 'calibrated' or 'fixed', not '" + std::string(w[2]) + "'");
      }
      f.calibrate_terminals = w[2] == "calibrated";
      return true;
    }
    double v = 0.0;
    if (key == "inflow" || key == "outlet") {
      const bool outlet = key == "outlet";
      if (!flow_args(w, 2, 2) || !flow_value_in(w, 3, 0.0, 40000.0, outlet, outlet ? "(0, 40000] mL/min" : "[0, 40000] mL/min", v)) {
        return false;
      }
      return flow_segment_setting(f, w, outlet ? f.outlets : f.inflows, v);
    }
    if (key == "closed") {
      v = f.sac_exchange_fraction;
      if (!flow_args(w, 1, 2) || (w.size() == 4 && !flow_value_in(w, 3, 0.0, 1.0, false, "[0, 1]", v))) return false;
      return flow_segment_setting(f, w, f.closed, v);
    }
    return error_here("flow: unknown setting '" + std::string(key) +
                      "' (known: viscosity cardiac_output cerebral_fraction pressure wall_shear_stress dispersion "
                      "pulsatile terminals inflow outlet closed)");
  }

  // `flow KEY ...` has lo..hi values after its key.
  bool flow_args(const std::vector<std::string_view>& w, std::size_t lo, std::size_t hi) {
    const std::size_t n = w.size() - 2;
    if (n >= lo && n <= hi) return true;
    return error_here("flow " + std::string(w[1]) + ": expected " + std::to_string(lo) + (hi > lo ? " or " + std::to_string(hi) : "") +
                      " value" + (hi == 1 ? "" : "s") + ", got " + std::to_string(n));
  }

  // Word i of a flow line, a number in the range (lo open or closed, hi closed).
  bool flow_value_in(const std::vector<std::string_view>& w, std::size_t i, double lo, double hi, bool lo_open, const char* range,
                     double& out) {
    const std::string what = "flow " + std::string(w[1]);
    if (!number(w[i], what, out)) return false;
    if ((lo_open ? out <= lo : out < lo) || out > hi) return error_here(what + ": " + std::string(w[i]) + " is not in " + range);
    return true;
  }

  // `flow KEY VALUE`, once per case.
  bool flow_scalar(const std::vector<std::string_view>& w, double& field, double lo, double hi, bool lo_open, const char* range) {
    if (!flow_args(w, 1, 1) || !once_flow(w[1])) return false;
    return flow_value_in(w, 2, lo, hi, lo_open, range, field);
  }

  // `flow inflow|outlet|closed SEG ...`: a segment given once as an outlet or closed (an
  // inflow may also be either), at most kMaxFlowSettings in all.
  bool flow_segment_setting(flow::FlowSettings& f, const std::vector<std::string_view>& w, std::vector<flow::SegmentSetting>& list,
                            double value) {
    const std::string what = "flow " + std::string(w[1]);
    double id = 0.0;
    if (!number(w[2], what, id)) return false;
    if (id != std::floor(id) || id < -2147483648.0 || id > 2147483647.0) return error_here(what + ": segment id must be a 32-bit integer");
    const auto seg = static_cast<std::int32_t>(id);
    for (const auto* other : {&f.inflows, &f.outlets, &f.closed}) {
      for (const flow::SegmentSetting& o : *other) {
        const bool same_list = other == &list;
        const bool clash = same_list || (other != &f.inflows && &list != &f.inflows);
        if (o.segment_id == seg && clash) {
          return error_here(what + ": segment " + std::to_string(seg) + " already given on line " + std::to_string(o.line));
        }
      }
    }
    if (f.inflows.size() + f.outlets.size() + f.closed.size() >= kMaxFlowSettings) return error_here("too many flow settings");
    list.push_back(flow::SegmentSetting{seg, value, lines_.line()});
    return true;
  }

  bool once_flow(std::string_view key) {
    for (const std::string& k : flow_keys_) {
      if (k == key) return error_here("flow " + std::string(key) + " given twice");
    }
    flow_keys_.emplace_back(key);
    return true;
  }

  bool check_tool(const ToolSpec& t, std::size_t line) {
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

  // The words w[first..] as key=NUMBER pairs, each handed to on_pair(key, value), which returns
  // false once it has reported an error. `what` names the statement in the errors.
  template <class OnPair>
  bool number_pairs(const std::vector<std::string_view>& w, std::size_t first, std::string_view what, OnPair on_pair) {
    for (std::size_t i = first; i < w.size(); ++i) {
      const std::size_t eq = w[i].find('=');
      if (eq == std::string_view::npos) return error_here(std::string(what) + ": expected key=value, got '" + std::string(w[i]) + "'");
      const std::string_view k = w[i].substr(0, eq);
      double v = 0.0;
      if (!number(w[i].substr(eq + 1), std::string(what) + " " + std::string(k), v) || !on_pair(k, v)) return false;
    }
    return true;
  }

  bool expect_args(const std::vector<std::string_view>& w, std::size_t n) {
    if (w.size() == n + 1) return true;
    return error_here(std::string(w[0]) + ": expected " + std::to_string(n) + " value" + (n == 1 ? "" : "s") + ", got " +
                      std::to_string(w.size() - 1));
  }
  bool once(bool& seen, std::string_view key) {
    if (seen) return error_here(std::string(key) + " given twice");
    seen = true;
    return true;
  }
  bool number(std::string_view word, const std::string& what, double& out) {
    const std::optional<double> v = parse_number(word);
    if (!v) return error_here(what + ": '" + std::string(word) + "' is not a finite number");
    out = *v;
    return true;
  }
  bool numbers(const std::vector<std::string_view>& w, std::size_t first, double* out, std::size_t n) {
    for (std::size_t i = 0; i < n; ++i) {
      if (!number(w[first + i], std::string(w[0]), out[i])) return false;
    }
    return true;
  }
  bool error_here(const std::string& message) { return error_at(lines_.line(), message); }
  bool error_at(std::size_t line, const std::string& message) {
    error_ = located(file_, line, message);
    return false;
  }
  CaseParse fail() { return base::Error{error_}; }
  CaseParse fail_here(const std::string& message) {
    error_here(message);
    return fail();
  }
  CaseParse fail_at(std::size_t line, const std::string& message) {
    error_at(line, message);
    return fail();
  }

  TextLines lines_;
  std::string_view file_;
  std::string error_;
  Case c_;
  Seen seen_;
  ToolSpec* tool_ = nullptr;  // the tool whose lines are being read (c_.tools' last), or none
  std::size_t tool_line_ = 0;
  std::vector<std::size_t> tool_lines_;  // each tool's `tool` line
  std::vector<std::string> flow_keys_;
  std::size_t stent_line_ = 0;  // the last stent_retriever statement
};

}  // namespace

CaseParse parse_case(std::string_view text, std::string_view file_name) {
  return CaseParser(text, file_name).run();
}

CaseParse load_case(const std::string& path) {
  const base::Result<std::string, base::ReadFileError> text = base::read_file(path, kMaxCaseBytes);
  if (!text) return base::Error{path + ":0: cannot read the file (missing, unreadable or larger than 16 MiB)"};
  return parse_case(*text, path);
}

ToolSpec default_guidewire() {
  ToolSpec spec;
  spec.name = "guidewire";
  spec.kind = ToolKind::kGuidewire;
  // 0.014" nitinol wire: stiff shaft, tapered core, soft distal 15 mm with a 45 degree tip.
  spec.sections = {ToolSection{1750.0, 0.36, 40.0, 31.0, 0.0}, ToolSection{35.0, 0.36, 3.0, 2.3, 0.0},
                   ToolSection{12.0, 0.36, 0.3, 0.23, 0.0}, ToolSection{3.0, 0.36, 0.3, 0.23, 45.0}};
  spec.friction = 0.08;
  return spec;
}

ToolSpec default_catheter() {
  ToolSpec spec;
  spec.name = "catheter";
  spec.kind = ToolKind::kCatheter;
  // 5F braided catheter with a softer distal 40 mm and a slight angle at the tip.
  spec.sections = {ToolSection{960.0, 1.67, 250.0, 190.0, 0.0}, ToolSection{30.0, 1.67, 40.0, 30.0, 0.0},
                   ToolSection{10.0, 1.67, 20.0, 15.0, 30.0}};
  spec.friction = 0.15;
  spec.inner_diameter_mm = 1.0;
  return spec;
}

ToolSpec default_microcatheter() {
  ToolSpec spec;
  spec.name = "microcatheter";
  spec.kind = ToolKind::kCatheter;
  spec.sections = {ToolSection{1500.0, 0.7, 2.0, 1.6, 0.0}};
  spec.inner_diameter_mm = 0.45;
  spec.friction = 0.1;
  spec.max_spacing_mm = 1.0;
  return spec;
}

ToolSpec default_coil(double length_mm, double loop_diameter_mm) {
  ToolSpec spec;
  spec.name = "coil";
  spec.kind = ToolKind::kCoil;
  ToolSection wind{length_mm, 0.25, 0.02, 0.016, 0.0};
  wind.shape = CoilShape::kHelix;
  wind.loop_diameter_mm = loop_diameter_mm;
  spec.sections = {ToolSection{1800.0, 0.33, 10.0, 8.0, 0.0}, wind};
  spec.detach_mm = length_mm;
  spec.inside = "microcatheter";
  spec.friction = 0.05;
  spec.max_spacing_mm = 1.0;
  spec.tip_spacing_mm = 0.5;
  spec.tip_zone_mm = length_mm + 2.0;
  return spec;
}

}  // namespace cathbox::tool
