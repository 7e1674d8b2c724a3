// The case file's reader: the loop over its lines and the case's own statements and checks.
#include "case_parser.hpp"

#include <cmath>
#include <filesystem>
#include <utility>

#include <glm/geometric.hpp>

#include "tool/aneurysm_sac.hpp"

namespace cathbox::tool::detail {

CaseParse CaseParser::run() {
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

// A line between `tool NAME KIND` and its `end`.
bool CaseParser::in_tool_statement(const std::vector<std::string_view>& w) {
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
bool CaseParser::statement(const std::vector<std::string_view>& w) {
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

bool CaseParser::header_statement(const std::vector<std::string_view>& w) {
  if (!expect_args(w, 1) || !once(seen_.header, w[0])) return false;
  if (w[1] != "1") return error_here("unsupported case version '" + std::string(w[1]) + "' (known: 1)");
  return true;
}

bool CaseParser::name_statement(const std::vector<std::string_view>& w) {
  if (w.size() < 2) return error_here("name: missing value");
  if (!once(seen_.name, w[0])) return false;
  c_.name = std::string(w[1]);
  for (std::size_t i = 2; i < w.size(); ++i) c_.name += " " + std::string(w[i]);
  return true;
}

bool CaseParser::threshold_statement(const std::vector<std::string_view>& w) {
  double v[1];
  if (!expect_args(w, 1) || !once(seen_.threshold, w[0]) || !numbers(w, 1, v, 1)) return false;
  if (!(v[0] > 0.0) || v[0] > 1e6) return error_here("wall_force_threshold: mN must be in (0, 1e6]");
  c_.wall_force_threshold_mN = v[0];
  return true;
}

bool CaseParser::valve_statement(const std::vector<std::string_view>& w) {
  double v[1];
  if (!expect_args(w, 1) || !once(seen_.valve, w[0]) || !numbers(w, 1, v, 1)) return false;
  if (v[0] < 0.0 || v[0] > ToolLimits::kMaxValveFriction_mN) return error_here("valve_friction must be in [0, 2000] mN");
  c_.valve_friction_mN = v[0];
  return true;
}

bool CaseParser::realistic_statement(const std::vector<std::string_view>& w) {
  if (!expect_args(w, 0) || !once(seen_.realistic, w[0])) return false;
  c_.realistic = true;
  return true;
}

// `vessel FILE` or `surface FILE`: the path relative to the case file's folder.
bool CaseParser::path_statement(const std::vector<std::string_view>& w) {
  if (!expect_args(w, 1)) return false;
  std::string& path = w[0] == "vessel" ? c_.vessel_path : c_.surface_path;
  if (!path.empty()) return error_here(std::string(w[0]) + " given twice");
  if (w[0] == "surface") surface_line_ = lines_.line();
  std::filesystem::path p{std::string(w[1])};
  if (p.is_relative()) p = std::filesystem::path{std::string(file_)}.parent_path() / p;
  path = p.lexically_normal().string();
  return true;
}

bool CaseParser::tube_statement(const std::vector<std::string_view>& w) {
  double v[9];
  if (!expect_args(w, 9) || !numbers(w, 1, v, 9)) return false;
  if (c_.tubes.size() >= kMaxTubes) return error_here("too many tubes (at most 200000)");
  if (v[0] != std::floor(v[0]) || std::abs(v[0]) > 2e9) return error_here("tube: segment id must be an integer");
  if (v[4] <= 0.0 || v[8] <= 0.0) return error_here("tube: radius must be > 0");
  c_.tubes.push_back(Tube{{v[1], v[2], v[3]}, {v[5], v[6], v[7]}, v[4], v[8], static_cast<std::int32_t>(v[0])});
  return true;
}

bool CaseParser::entry_statement(const std::vector<std::string_view>& w) {
  double v[6];
  if (!expect_args(w, 6) || !once(seen_.entry, w[0]) || !numbers(w, 1, v, 6)) return false;
  const glm::dvec3 d(v[3], v[4], v[5]);
  const double len = glm::length(d);
  if (!(len > 1e-9) || !std::isfinite(len)) return error_here("entry: direction must not be zero");
  c_.entry = Entry{{v[0], v[1], v[2]}, d / len};
  return true;
}

bool CaseParser::target_statement(const std::vector<std::string_view>& w) {
  double v[2];
  if (!expect_args(w, 2) || !once(seen_.target, w[0]) || !numbers(w, 1, v, 2)) return false;
  if (v[0] != std::floor(v[0]) || v[0] < 0 || v[0] > 2e9) return error_here("target: segment id must be an integer >= 0");
  if (v[1] < 0.0 || v[1] > 1.0) return error_here("target: fraction must be in [0, 1]");
  c_.target = CaseTarget{static_cast<std::int32_t>(v[0]), v[1]};
  return true;
}

bool CaseParser::aneurysm_statement(const std::vector<std::string_view>& w) {
  double v[7];
  if (!expect_args(w, 7) || !once(seen_.aneurysm, w[0]) || !numbers(w, 1, v, 7)) return false;
  if (v[3] < 1.0 || v[3] > 15.0) return error_here("aneurysm: dome radius must be in [1, 15] mm");
  c_.aneurysm = sphere_cap_sac({v[0], v[1], v[2]}, v[3], {v[4], v[5], v[6]});
  if (!c_.aneurysm) return error_here("aneurysm: the neck centre must lie inside the dome sphere, off its centre");
  return true;
}

bool CaseParser::view_statement(const std::vector<std::string_view>& w) {
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

bool CaseParser::wall_statement(const std::vector<std::string_view>& w) {
  // `wall TERRITORY` alone: the radius is the vessel's (its graph's median, case_wall.hpp).
  double v[1] = {0.0};
  if (w.size() == 2) {
    if (!once(seen_.wall, w[0])) return false;
  } else if (!expect_args(w, 2) || !once(seen_.wall, w[0]) || !numbers(w, 2, v, 1)) {
    return false;
  }
  CaseWall cw;
  if (w[1] == "cervical") {
    cw.territory = Territory::kCervical;
  } else if (w[1] == "intracranial") {
    cw.territory = Territory::kIntracranial;
  } else {
    return error_here("wall: territory must be 'cervical' or 'intracranial', not '" + std::string(w[1]) + "'");
  }
  if (w.size() > 2 && (v[0] < 0.5 || v[0] > 15.0)) return error_here("wall: lumen radius must be in [0.5, 15] mm");
  cw.radius_mm = v[0];
  c_.wall = cw;
  return true;
}

// After the last line: a vessel in one form, and what a surface needs.
bool CaseParser::check_vessel() {
  const std::size_t last = lines_.line();
  if (c_.vessel_path.empty() && c_.tubes.empty()) return error_at(last, "no vessel: give 'vessel FILE' or 'tube' lines");
  if (!c_.vessel_path.empty() && !c_.tubes.empty()) return error_at(last, "give either 'vessel' or 'tube' lines, not both");
  if (!c_.surface_path.empty() && c_.vessel_path.empty()) {
    return error_at(last, "a 'surface' needs a 'vessel' (its centreline graph: route, targets, flow)");
  }
  // The angioplasty unit re-meshes the wall from the vessel's centrelines at every inflation: a
  // given surface would be swapped for that mesh on the first one, so the two are not combined.
  for (const ToolSpec& t : c_.tools) {
    if (!c_.surface_path.empty() && t.balloon.present()) {
      return error_at(surface_line_, "a 'surface' case cannot carry a balloon (tool '" + t.name +
                                         "'): angioplasty re-meshes the wall from the 'vessel''s centrelines");
    }
  }
  if (c_.wall && c_.wall->radius_mm == 0.0 && c_.vessel_path.empty()) {
    return error_at(last, "a 'wall' without a radius takes the 'vessel''s: give 'wall TERRITORY RADIUS_MM' with tubes");
  }
  if (c_.tubes.size() > 0 && !c_.entry) return error_at(last, "analytic tubes need an 'entry'");
  return true;
}

bool CaseParser::check_aspiration() {
  for (const CaseAspiration& a : c_.aspiration) {
    for (const ToolSpec& t : c_.tools) {
      if (t.name == a.tool && !(t.inner_diameter_mm > 0.0)) return error_at(a.line, "aspiration: tool '" + t.name + "' has no inner_diameter");
    }
  }
  steer_aspiration_catheters(c_);
  return true;
}

}  // namespace cathbox::tool::detail
