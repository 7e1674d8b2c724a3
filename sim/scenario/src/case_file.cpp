#include "scenario/case_file.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

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
    Case c;
    std::vector<std::string_view> w;
    bool seen_header = false, seen_name = false, seen_entry = false, seen_target = false, seen_realistic = false, seen_valve = false,
         seen_threshold = false, seen_aneurysm = false, seen_wall = false;
    ToolSpec* tool = nullptr;
    std::size_t tool_line = 0;
    std::vector<std::size_t> tool_lines;
    while (lines_.next(w)) {
      const std::string_view key = w[0];
      if (tool != nullptr) {
        if (key == "end") {
          if (!expect_args(w, 0)) return fail();
          if (tool->sections.empty()) return fail_at(tool_line, "tool '" + tool->name + "' has no section");
          if (!check_tool(*tool, tool_line)) return fail();
          tool = nullptr;
        } else if (key == "aspiration") {
          if (!aspiration_statement(c, *tool, w)) return fail();
        } else if (!tool_statement(*tool, w)) {
          return fail();
        }
        continue;
      }
      if (key == "cathbox-case") {
        if (!expect_args(w, 1) || !once(seen_header, key)) return fail();
        if (w[1] != "1") return fail_here("unsupported case version '" + std::string(w[1]) + "' (known: 1)");
      } else if (key == "name") {
        if (w.size() < 2 || !once(seen_name, key)) return w.size() < 2 ? fail_here("name: missing value") : fail();
        c.name = std::string(w[1]);
        for (std::size_t i = 2; i < w.size(); ++i) c.name += " " + std::string(w[i]);
      } else if (key == "vessel" || key == "surface") {
        if (!expect_args(w, 1)) return fail();
        std::string& path = key == "vessel" ? c.vessel_path : c.surface_path;
        if (!path.empty()) return fail_here(std::string(key) + " given twice");
        std::filesystem::path p{std::string(w[1])};
        if (p.is_relative()) p = std::filesystem::path{std::string(file_)}.parent_path() / p;
        path = p.lexically_normal().string();
      } else if (key == "tube") {
        double v[9];
        if (!expect_args(w, 9) || !numbers(w, 1, v, 9)) return fail();
        if (c.tubes.size() >= kMaxTubes) return fail_here("too many tubes (at most 200000)");
        if (v[0] != std::floor(v[0]) || std::abs(v[0]) > 2e9) return fail_here("tube: segment id must be an integer");
        if (v[4] <= 0.0 || v[8] <= 0.0) return fail_here("tube: radius must be > 0");
        c.tubes.push_back(Tube{{v[1], v[2], v[3]}, {v[5], v[6], v[7]}, v[4], v[8], static_cast<std::int32_t>(v[0])});
      } else if (key == "entry") {
        double v[6];
        if (!expect_args(w, 6) || !once(seen_entry, key) || !numbers(w, 1, v, 6)) return fail();
        const glm::dvec3 d(v[3], v[4], v[5]);
        const double len = glm::length(d);
        if (!(len > 1e-9) || !std::isfinite(len)) return fail_here("entry: direction must not be zero");
        c.entry = Entry{{v[0], v[1], v[2]}, d / len};
      } else if (key == "target") {
        double v[2];
        if (!expect_args(w, 2) || !once(seen_target, key) || !numbers(w, 1, v, 2)) return fail();
        if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 2e9) return fail_here("target: segment id must be an integer >= 0");
        if (v[1] < 0.0 || v[1] > 1.0) return fail_here("target: fraction must be in [0, 1]");
        c.target = CaseTarget{static_cast<std::int32_t>(v[0]), v[1]};
      } else if (key == "wall_force_threshold") {
        double v[1];
        if (!expect_args(w, 1) || !once(seen_threshold, key) || !numbers(w, 1, v, 1)) return fail();
        if (!(v[0] > 0.0) || v[0] > 1e6) return fail_here("wall_force_threshold: mN must be in (0, 1e6]");
        c.wall_force_threshold_mN = v[0];
      } else if (key == "tool") {
        if (!expect_args(w, 2)) return fail();
        if (c.tools.size() >= kMaxTools) return fail_here("too many tools (at most 4)");
        for (const ToolSpec& t : c.tools) {
          if (t.name == w[1]) return fail_here("tool '" + std::string(w[1]) + "' defined twice");
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
          return fail_here("tool: kind must be 'guidewire', 'catheter' or 'coil', not '" + std::string(w[2]) + "'");
        }
        c.tools.push_back(spec);
        tool = &c.tools.back();
        tool_line = lines_.line();
        tool_lines.push_back(tool_line);
      } else if (key == "aneurysm") {
        double v[7];
        if (!expect_args(w, 7) || !once(seen_aneurysm, key) || !numbers(w, 1, v, 7)) return fail();
        if (v[3] < 1.0 || v[3] > 15.0) return fail_here("aneurysm: dome radius must be in [1, 15] mm");
        c.aneurysm = sphere_cap_sac({v[0], v[1], v[2]}, v[3], {v[4], v[5], v[6]});
        if (!c.aneurysm) return fail_here("aneurysm: the neck centre must lie inside the dome sphere, off its centre");
      } else if (key == "view") {
        double v[2];
        if (!expect_args(w, 3) || !numbers(w, 2, v, 2)) return fail();
        if (c.views.size() >= kMaxViews) return fail_here("too many views (at most 16)");
        for (const flow::NamedProjection& other : c.views) {
          if (other.name == w[1]) return fail_here("view '" + std::string(w[1]) + "' defined twice");
        }
        if (std::abs(v[0]) > 120.0) return fail_here("view: LAO/RAO angle must be within +-120 degrees");
        if (std::abs(v[1]) > 60.0) return fail_here("view: cranial/caudal angle must be within +-60 degrees");
        c.views.push_back(flow::NamedProjection{std::string(w[1]), v[0], v[1]});
      } else if (key == "valve_friction") {
        double v[1];
        if (!expect_args(w, 1) || !once(seen_valve, key) || !numbers(w, 1, v, 1)) return fail();
        if (v[0] < 0.0 || v[0] > ToolLimits::kMaxValveFriction_mN) return fail_here("valve_friction must be in [0, 2000] mN");
        c.valve_friction_mN = v[0];
      } else if (key == "wall") {
        double v[1];
        if (!expect_args(w, 2) || !once(seen_wall, key) || !numbers(w, 2, v, 1)) return fail();
        CaseWall cw;
        if (w[1] == "cervical") {
          cw.territory = Territory::kCervical;
        } else if (w[1] == "intracranial") {
          cw.territory = Territory::kIntracranial;
        } else {
          return fail_here("wall: territory must be 'cervical' or 'intracranial', not '" + std::string(w[1]) + "'");
        }
        if (v[0] < 0.5 || v[0] > 15.0) return fail_here("wall: lumen radius must be in [0.5, 15] mm");
        cw.radius_mm = v[0];
        c.wall = cw;
      } else if (key == "realistic") {
        if (!expect_args(w, 0) || !once(seen_realistic, key)) return fail();
        c.realistic = true;
      } else if (key == "flow") {
        if (!flow_statement(c.flow, w)) return fail();
      } else if (key == "clot") {
        if (!clot_statement(c, w)) return fail();
      } else if (key == "end") {
        return fail_here("'end' without a tool");
      } else {
        return fail_here("unknown keyword '" + std::string(key) + "'");
      }
    }
    if (tool != nullptr) return fail_at(tool_line, "tool '" + tool->name + "' has no 'end'");
    if (c.vessel_path.empty() && c.tubes.empty()) return fail_at(lines_.line(), "no vessel: give 'vessel FILE' or 'tube' lines");
    if (!c.vessel_path.empty() && !c.tubes.empty()) return fail_at(lines_.line(), "give either 'vessel' or 'tube' lines, not both");
    if (!c.surface_path.empty() && c.vessel_path.empty()) {
      return fail_at(lines_.line(), "a 'surface' needs a 'vessel' (its centreline graph: route, targets, flow)");
    }
    if (!c.surface_path.empty() && c.wall) {
      return fail_at(lines_.line(), "a compliant 'wall' is re-meshed from the vessel's centrelines: it cannot take a 'surface'");
    }
    if (c.tubes.size() > 0 && !c.entry) return fail_at(lines_.line(), "analytic tubes need an 'entry'");
    // Coaxial references.
    for (std::size_t i = 0; i < c.tools.size(); ++i) {
      const ToolSpec& t = c.tools[i];
      if (t.inside.empty()) continue;
      const ToolSpec* outer = nullptr;
      for (const ToolSpec& o : c.tools) if (o.name == t.inside) outer = &o;
      if (outer == nullptr) return fail_at(tool_lines[i], "tool '" + t.name + "': inside unknown tool '" + t.inside + "'");
      if (outer == &t) return fail_at(tool_lines[i], "tool '" + t.name + "' cannot be inside itself");
      if (nesting_cycle(c.tools, i)) return fail_at(tool_lines[i], "tool '" + t.name + "': the tools it runs in run inside it");
      if (outer->kind != ToolKind::kCatheter) return fail_at(tool_lines[i], "tool '" + t.name + "': '" + outer->name + "' is not a catheter");
      const double od = t.max_outer_diameter_mm();
      if (outer->inner_diameter_mm <= od) {
        return fail_at(tool_lines[i], "tool '" + t.name + "' (od " + std::to_string(od) + " mm) does not fit in '" + outer->name + "'");
      }
    }
    for (const CaseAspiration& a : c.aspiration) {
      for (const ToolSpec& t : c.tools) {
        if (t.name == a.tool && !(t.inner_diameter_mm > 0.0)) return fail_at(a.line, "aspiration: tool '" + t.name + "' has no inner_diameter");
      }
    }
    if (c.tools.empty()) c.tools.push_back(default_guidewire());
    // One blood and one sheath for the whole case: the tools' drag follows the flow model's
    // viscosity; the case's valve friction is the default of every tool that gives none.
    for (ToolSpec& t : c.tools) {
      t.blood_viscosity_mPa_s = c.flow.viscosity_mPa_s;
      if (!t.valve_friction_mN && c.valve_friction_mN) t.valve_friction_mN = c.valve_friction_mN;
    }
    c.flow.source = std::string(file_);
    return c;
  }

 private:
  bool tool_statement(ToolSpec& t, const std::vector<std::string_view>& w) {
    const std::string_view key = w[0];
    if (key == "section") {
      if (t.sections.size() >= kMaxSections) return error_here("too many sections (at most 64)");
      ToolSection s;
      if (!section_words(w, t.kind, s)) return false;
      t.sections.push_back(s);
      return true;
    }
    if (key == "next_coil") {
      if (t.kind != ToolKind::kCoil) return error_here("next_coil is for coil tools");
      if (t.next_coils.size() >= kMaxNextCoils) return error_here("too many next coils (at most 15)");
      ToolSection s;
      if (!section_words(w, t.kind, s)) return false;
      if (s.length_mm > 300.0) return error_here("next_coil: coil length must be in (0, 300] mm");
      if (s.shape == CoilShape::kNone) return error_here("next_coil: shape= and loop= are required");
      t.next_coils.push_back(s);
      return true;
    }
    double v = 0.0;
    if (key == "friction") {
      if (!expect_args(w, 1) || !number(w[1], "friction", v)) return false;
      if (v < 0.0 || v > 2.0) return error_here("friction must be in [0, 2]");
      t.friction = v;
    } else if (key == "inner_diameter") {
      if (!expect_args(w, 1) || !number(w[1], "inner_diameter", v)) return false;
      if (v < 0.0 || v > 20.0) return error_here("inner_diameter must be in [0, 20] mm");
      t.inner_diameter_mm = v;
    } else if (key == "inside") {
      if (!expect_args(w, 1)) return false;
      t.inside = std::string(w[1]);
    } else if (key == "spacing") {
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
    } else if (key == "drag") {
      if (!expect_args(w, 1) || !number(w[1], "drag", v)) return false;
      if (v < 0.0 || v > 10.0) return error_here("drag must be in [0, 10] mN.s/mm2");
      t.drag_mN_s_per_mm2 = v;
    } else if (key == "valve_friction") {
      if (!expect_args(w, 1) || !number(w[1], "valve_friction", v)) return false;
      if (v < 0.0 || v > ToolLimits::kMaxValveFriction_mN) return error_here("valve_friction must be in [0, 2000] mN");
      t.valve_friction_mN = v;
    } else if (key == "detach") {
      if (!expect_args(w, 1) || !number(w[1], "detach", v)) return false;
      if (t.kind != ToolKind::kCoil) return error_here("detach is for coil tools");
      if (v <= 0.0 || v > 300.0) return error_here("detach: coil length must be in (0, 300] mm");
      t.detach_mm = v;
    } else if (key == "balloon") {
      return balloon_statement(t, w);
    } else if (key == "stent_retriever") {
      return stent_statement(t, w);
    } else if (key == "axial_stiffness") {
      if (!expect_args(w, 1) || !number(w[1], "axial_stiffness", v)) return false;
      if (v < 10.0 || v > 1e6) return error_here("axial_stiffness must be in [10, 1e6] N");
      t.axial_stiffness_N = v;
    } else {
      return error_here("unknown tool keyword '" + std::string(key) + "'");
    }
    return true;
  }

  // `section` and `next_coil`: LENGTH od=MM ei=N.mm2 gj=N.mm2 [curve=DEG] [shape=... loop=MM].
  bool section_words(const std::vector<std::string_view>& w, ToolKind kind, ToolSection& s) {
    const std::string verb(w[0]);
    if (w.size() < 2) return error_here(verb + ": missing length");
    double len = 0.0;
    if (!number(w[1], verb + " length", len)) return false;
    if (len <= 0.0) return error_here(verb + ": length must be > 0");
    s.length_mm = len;
    bool od = false, ei = false, gj = false;
    for (std::size_t i = 2; i < w.size(); ++i) {
      const std::size_t eq = w[i].find('=');
      if (eq == std::string_view::npos) return error_here(verb + ": expected key=value, got '" + std::string(w[i]) + "'");
      const std::string_view k = w[i].substr(0, eq);
      if (k == "shape") {
        const std::string_view name = w[i].substr(eq + 1);
        if (name == "helix") {
          s.shape = CoilShape::kHelix;
        } else if (name == "complex") {
          s.shape = CoilShape::kComplex;
        } else {
          return error_here(verb + ": shape must be 'helix' or 'complex', not '" + std::string(name) + "'");
        }
        continue;
      }
      double v = 0.0;
      if (!number(w[i].substr(eq + 1), std::string(k), v)) return false;
      if (k == "loop") {
        if (v < 2.0 || v > 20.0) return error_here(verb + ": loop diameter must be in [2, 20] mm");
        s.loop_diameter_mm = v;
      } else if (k == "od") {
        if (v <= 0.0 || v > 20.0) return error_here(verb + ": od must be in (0, 20] mm");
        s.outer_diameter_mm = v;
        od = true;
      } else if (k == "ei") {
        if (v <= 0.0 || v > 1e6) return error_here(verb + ": ei must be in (0, 1e6] N.mm2");
        s.bending_stiffness_Nmm2 = v;
        ei = true;
      } else if (k == "gj") {
        if (v <= 0.0 || v > 1e6) return error_here(verb + ": gj must be in (0, 1e6] N.mm2");
        s.torsion_stiffness_Nmm2 = v;
        gj = true;
      } else if (k == "curve") {
        if (std::abs(v) > 360.0) return error_here(verb + ": curve must be within +-360 degrees");
        s.curve_deg = v;
      } else {
        return error_here(verb + ": unknown key '" + std::string(k) + "' (known: od ei gj curve shape loop)");
      }
    }
    if (!od || !ei || !gj) return error_here(verb + ": od=, ei= and gj= are required");
    if ((s.shape != CoilShape::kNone) != (s.loop_diameter_mm > 0.0)) return error_here(verb + ": shape= and loop= go together");
    if (s.shape != CoilShape::kNone && kind != ToolKind::kCoil) return error_here(verb + ": shape= is for coil tools");
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
    const std::string what = "flow " + std::string(key);
    const auto args = [&](std::size_t lo, std::size_t hi) {
      const std::size_t n = w.size() - 2;
      if (n >= lo && n <= hi) return true;
      return error_here(what + ": expected " + std::to_string(lo) + (hi > lo ? " or " + std::to_string(hi) : "") +
                        " value" + (hi == 1 ? "" : "s") + ", got " + std::to_string(n));
    };
    const auto value_in = [&](std::size_t i, double lo, double hi, bool lo_open, const char* range, double& out) {
      if (!number(w[i], what, out)) return false;
      if ((lo_open ? out <= lo : out < lo) || out > hi) return error_here(what + ": " + std::string(w[i]) + " is not in " + range);
      return true;
    };
    const auto scalar = [&](double& field, double lo, double hi, bool lo_open, const char* range) {
      if (!args(1, 1) || !once_flow(key)) return false;
      return value_in(2, lo, hi, lo_open, range, field);
    };
    const auto segment_setting = [&](std::vector<flow::SegmentSetting>& list, double value) {
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
    };
    if (key == "viscosity") return scalar(f.viscosity_mPa_s, 0.5, 20.0, false, "[0.5, 20] mPa.s");
    if (key == "cardiac_output") return scalar(f.cardiac_output_ml_min, 500.0, 40000.0, false, "[500, 40000] mL/min");
    if (key == "cerebral_fraction") return scalar(f.cerebral_fraction, 0.0, 0.5, true, "(0, 0.5]");
    if (key == "wall_shear_stress") return scalar(f.wall_shear_stress_Pa, 0.0, 20.0, true, "(0, 20] Pa");
    if (key == "dispersion") return scalar(f.dispersion_radii, 0.0, 20.0, false, "[0, 20] radii");
    if (key == "pressure") {
      if (!args(2, 2) || !once_flow(key) || !value_in(2, 20.0, 250.0, false, "[20, 250] mmHg", f.arterial_pressure_mmHg) ||
          !value_in(3, 0.0, 50.0, false, "[0, 50] mmHg", f.venous_pressure_mmHg)) {
        return false;
      }
      if (f.venous_pressure_mmHg >= f.arterial_pressure_mmHg) return error_here(what + ": venous must be below arterial pressure");
      return true;
    }
    if (key == "pulsatile") {
      return args(2, 2) && once_flow(key) && value_in(2, 0.0, 300.0, true, "(0, 300] bpm", f.heart_rate_bpm) &&
             value_in(3, 0.0, 2.0, false, "[0, 2]", f.pulsatility_index);
    }
    if (key == "terminals") {
      if (!args(1, 1) || !once_flow(key)) return false;
      if (w[2] != "calibrated" && w[2] != "fixed") return error_here(what + ": expected 'calibrated' or 'fixed', not '" + std::string(w[2]) + "'");
      f.calibrate_terminals = w[2] == "calibrated";
      return true;
    }
    double v = 0.0;
    if (key == "inflow" || key == "outlet") {
      if (!args(2, 2) || !value_in(3, 0.0, 40000.0, key == "outlet", key == "outlet" ? "(0, 40000] mL/min" : "[0, 40000] mL/min", v)) {
        return false;
      }
      return segment_setting(key == "inflow" ? f.inflows : f.outlets, v);
    }
    if (key == "closed") {
      v = f.sac_exchange_fraction;
      if (!args(1, 2) || (w.size() == 4 && !value_in(3, 0.0, 1.0, false, "[0, 1]", v))) return false;
      return segment_setting(f.closed, v);
    }
    return error_here("flow: unknown setting '" + std::string(key) +
                      "' (known: viscosity cardiac_output cerebral_fraction pressure wall_shear_stress dispersion "
                      "pulsatile terminals inflow outlet closed)");
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
