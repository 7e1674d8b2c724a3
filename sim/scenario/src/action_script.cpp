#include "scenario/action_script.hpp"

#include <cmath>
#include <string>
#include <vector>

#include "base/read_file.hpp"
#include "base/text_lines.hpp"

namespace cathbox::tool {

using base::text::TextLines;
using base::text::located;
using base::text::parse_number;

namespace {
constexpr std::size_t kMaxScriptBytes = 8u << 20;
constexpr std::size_t kMaxActions = 200000;
constexpr double kMaxTime_ms = 3.6e6;  // one hour of virtual time

using Words = std::vector<std::string_view>;

// Each reader takes one verb's words (w[0] the time, w[1] the verb) into `a`, whose time is set:
// empty, or what is wrong with them.

std::string read_select(const Words& w, Action& a) {
  if (w.size() != 3) return "select: expected one tool name";
  a.kind = ActionKind::kSelect;
  a.tool = std::string(w[2]);
  return {};
}

// A verb that takes no arguments: end, detach, load_coil, deflate.
std::string read_bare(const Words& w, Action& a, ActionKind kind, const char* problem) {
  if (w.size() != 2) return problem;
  a.kind = kind;
  return {};
}

std::string read_fluoro_or_roadmap(const Words& w, Action& a) {
  const std::string_view verb = w[1];
  a.kind = verb == "fluoro" ? ActionKind::kFluoro : ActionKind::kRoadmap;
  const bool roadmap = a.kind == ActionKind::kRoadmap;
  if (roadmap && w.size() == 2) {
    a.value = 1.0;
  } else if (w.size() == 3 && (w[2] == "on" || w[2] == "off")) {
    a.value = w[2] == "on" ? 1.0 : 0.0;
  } else {
    return std::string(verb) + (roadmap ? ": expected nothing, 'on' or 'off'" : ": expected 'on' or 'off'");
  }
  return {};
}

std::string read_inject(const Words& w, Action& a) {
  a.kind = ActionKind::kInject;
  if (w.size() != 3 && w.size() != 5 && w.size() != 7) return "inject: expected VOLUME_ML [at RATE_ML_PER_S] [conc MGI_PER_ML]";
  const std::optional<double> v = parse_number(w[2]);
  if (!v || *v <= 0.0 || *v > 100.0) return "inject: volume must be in (0, 100] mL";
  a.value = *v;
  a.speed = kDefaultInjectRate_ml_s;
  bool rate_given = false;
  for (std::size_t i = 3; i + 1 < w.size(); i += 2) {
    const std::optional<double> x = parse_number(w[i + 1]);
    if (w[i] == "at" && !rate_given && a.concentration_mgI_ml == 0.0) {
      if (!x || *x <= 0.0 || *x > 30.0) return "inject: rate must be in (0, 30] mL/s";
      a.speed = *x;
      rate_given = true;
    } else if (w[i] == "conc" && a.concentration_mgI_ml == 0.0) {
      if (!x || *x <= 0.0 || *x > kMaxInjectConcentration_mgI_ml) return "inject: concentration must be in (0, 1000] mgI/mL";
      a.concentration_mgI_ml = *x;
    } else {
      return "inject: expected 'at RATE' and/or 'conc MGI_PER_ML' (in that order, each once), got '" + std::string(w[i]) + "'";
    }
  }
  return {};
}

std::string read_inflate(const Words& w, Action& a) {
  if (w.size() != 4 || (w[3] != "atm" && w[3] != "ml")) return "inflate: expected VALUE atm or VALUE ml";
  const bool atm = w[3] == "atm";
  a.kind = atm ? ActionKind::kInflatePressure : ActionKind::kInflateVolume;
  const std::optional<double> v = parse_number(w[2]);
  if (atm && (!v || *v < 0.0 || *v > kMaxInflate_atm)) return "inflate: pressure must be in [0, 30] atm";
  if (!atm && (!v || *v < 0.0 || *v > kMaxInflate_ml)) return "inflate: volume must be in [0, 20] ml";
  a.value = *v;
  return {};
}

std::string read_aspiration_or_guide(const Words& w, Action& a) {
  const std::string_view verb = w[1];
  const bool asp = verb == "aspiration";
  a.kind = asp ? ActionKind::kAspiration : ActionKind::kBalloonGuide;
  const std::string_view yes = asp ? "on" : "inflate";
  const std::string_view no = asp ? "off" : "deflate";
  if (w.size() != 3 || (w[2] != yes && w[2] != no)) {
    return std::string(verb) + ": expected '" + std::string(yes) + "' or '" + std::string(no) + "'";
  }
  a.value = w[2] == yes ? 1.0 : 0.0;
  return {};
}

std::string read_carm(const Words& w, Action& a) {
  a.kind = ActionKind::kCArm;
  if (w.size() != 4) return "carm: expected LAO_DEG CRANIAL_DEG (negative for RAO / caudal)";
  const std::optional<double> l = parse_number(w[2]);
  const std::optional<double> c = parse_number(w[3]);
  if (!l || std::abs(*l) > 120.0) return "carm: LAO/RAO angle must be within +-120 degrees";
  if (!c || std::abs(*c) > 60.0) return "carm: cranial/caudal angle must be within +-60 degrees";
  a.value = *l;
  a.value2 = *c;
  return {};
}

// insert_to, insert_by, rotate_to, rotate_by: VALUE [at SPEED].
std::string read_motion(const Words& w, Action& a) {
  const std::string_view verb = w[1];
  const bool insert = verb == "insert_to" || verb == "insert_by";
  a.kind = verb == "insert_to" ? ActionKind::kInsertTo
           : verb == "insert_by" ? ActionKind::kInsertBy
           : verb == "rotate_to" ? ActionKind::kRotateTo
                                 : ActionKind::kRotateBy;
  if (w.size() != 3 && w.size() != 5) return std::string(verb) + ": expected VALUE [at SPEED]";
  const std::optional<double> v = parse_number(w[2]);
  if (!v) return std::string(verb) + ": '" + std::string(w[2]) + "' is not a finite number";
  const double limit = insert ? 4000.0 : 36000.0;
  if (std::abs(*v) > limit || (a.kind == ActionKind::kInsertTo && *v < 0.0)) return std::string(verb) + ": value out of range";
  a.value = *v;
  a.speed = insert ? kDefaultInsertSpeed_mm_s : kDefaultRotateSpeed_deg_s;
  if (w.size() == 5) {
    if (w[3] != "at") return std::string(verb) + ": expected 'at SPEED', got '" + std::string(w[3]) + "'";
    const std::optional<double> s = parse_number(w[4]);
    const double max_speed = insert ? 1000.0 : 7200.0;
    if (!s || *s <= 0.0 || *s > max_speed) return std::string(verb) + ": speed must be in (0, " + std::to_string(static_cast<int>(max_speed)) + "]";
    a.speed = *s;
  }
  return {};
}

// The verb w[1] and its arguments into `a`: empty, or what is wrong.
std::string read_verb(const Words& w, Action& a) {
  const std::string_view verb = w[1];
  if (verb == "select") return read_select(w, a);
  if (verb == "end") return read_bare(w, a, ActionKind::kEnd, "end: takes no arguments");
  if (verb == "detach") return read_bare(w, a, ActionKind::kDetach, "detach: takes no arguments (it releases the selected tool's coil)");
  if (verb == "load_coil") {
    return read_bare(w, a, ActionKind::kLoadCoil, "load_coil: takes no arguments (it loads the selected coil tool's next coil)");
  }
  if (verb == "fluoro" || verb == "roadmap") return read_fluoro_or_roadmap(w, a);
  if (verb == "inject") return read_inject(w, a);
  if (verb == "inflate") return read_inflate(w, a);
  if (verb == "deflate") return read_bare(w, a, ActionKind::kDeflate, "deflate: takes no arguments");
  if (verb == "aspiration" || verb == "balloon_guide") return read_aspiration_or_guide(w, a);
  if (verb == "carm") return read_carm(w, a);
  if (verb == "insert_to" || verb == "insert_by" || verb == "rotate_to" || verb == "rotate_by") return read_motion(w, a);
  return "unknown verb '" + std::string(verb) +
         "' (known: select insert_to insert_by rotate_to rotate_by end fluoro inject carm roadmap detach load_coil inflate deflate aspiration balloon_guide)";
}

}  // namespace

ScriptParse parse_script(std::string_view text, std::string_view file_name) {
  Script script;
  TextLines lines(text);
  std::vector<std::string_view> w;
  std::int64_t last_time = 0;
  bool ended = false;
  auto fail = [&](const std::string& message) -> ScriptParse {
    return base::Error{located(file_name, lines.line(), message)};
  };
  while (lines.next(w)) {
    if (ended) return fail("action after 'end'");
    if (script.actions.size() >= kMaxActions) return fail("too many actions (at most 200000)");
    const std::optional<double> t = parse_number(w[0]);
    if (!t || *t < 0.0 || *t > kMaxTime_ms || *t != std::floor(*t)) {
      return fail("time '" + std::string(w[0]) + "' must be a whole number of milliseconds in [0, 3600000]");
    }
    Action a;
    a.time_ms = static_cast<std::int64_t>(*t);
    a.line = lines.line();
    if (a.time_ms < last_time) return fail("time " + std::to_string(a.time_ms) + " ms is before the previous action");
    last_time = a.time_ms;
    if (w.size() < 2) return fail("missing verb after the time");
    const std::string problem = read_verb(w, a);
    if (!problem.empty()) return fail(problem);
    ended = a.kind == ActionKind::kEnd;
    script.actions.push_back(std::move(a));
  }
  return script;
}

ScriptParse load_script(const std::string& path) {
  const base::Result<std::string, base::ReadFileError> text = base::read_file(path, kMaxScriptBytes);
  if (!text) return base::Error{path + ":0: cannot read the file (missing, unreadable or larger than 8 MiB)"};
  return parse_script(*text, path);
}

}  // namespace cathbox::tool
