#include "emu/hand_script.hpp"

#include <cmath>
#include <cstdlib>
#include <string>

namespace cathbox::emu {
namespace {

bool parse_duration(const std::string& text, uint64_t& us) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  const std::string unit(end);
  double scale = 0;
  if (unit == "s") scale = 1e6;
  if (unit == "ms") scale = 1e3;
  if (unit == "us") scale = 1;
  if (scale == 0 || end == text.c_str() || !std::isfinite(v) || v < 0 || v * scale > 1e15) return false;
  us = static_cast<uint64_t>(v * scale);
  return true;
}

// A value with its unit, in the project's units (mm and mN; rad): "20mm/s", "-1500mN",
// "3.14rad/s", "5mNmm". Converted to the model's SI units (m/s, N; rad/s, N*m). An old script
// in bare SI numbers ("v:0.02:2s") has no unit and is refused, never misread.
struct Unit {
  const char* name;
  HandMode mode;
  int axis;  // 0 insertion, 1 rotation
  double to_si;
};
constexpr Unit kUnits[] = {{"mm/s", HandMode::kVelocity, 0, 1e-3},
                           {"rad/s", HandMode::kVelocity, 1, 1.0},
                           {"mN", HandMode::kForce, 0, 1e-3},
                           {"mNmm", HandMode::kForce, 1, 1e-6}};

const char* unit_hint(HandMode mode) {
  return mode == HandMode::kVelocity ? "give a velocity in mm/s (insertion) or rad/s (rotation), e.g. v:20mm/s:2s"
                                     : "give a force in mN (insertion) or a torque in mNmm (rotation), e.g. f:-1500mN:1s";
}

// The VALUE:DURATION of a driven segment ("v:20mm/s:2s", "f:-1500mN:1s"; `a` and `b` its two
// colons) into `s`, whose mode is set; `script_axis` is the axis the script's units named so far
// (-1 before the first), `axis` the axis the caller drives (-1: either). Empty, or what is wrong.
std::string read_driven(const std::string& item, size_t a, size_t b, int axis, int& script_axis, HandSegment& s) {
  char* end = nullptr;
  const std::string value = item.substr(a + 1, b - a - 1);
  const double number = std::strtod(value.c_str(), &end);
  if (value.empty() || end == value.c_str() || !std::isfinite(number)) return "bad value";
  const std::string unit_name(end);
  const Unit* unit = nullptr;
  for (const Unit& u : kUnits) {
    if (u.mode == s.mode && unit_name == u.name) unit = &u;
  }
  if (unit == nullptr) {
    return (unit_name.empty() ? "the value has no unit" : "unit '" + unit_name + "' unknown") + ": " + unit_hint(s.mode);
  }
  if (axis >= 0 && unit->axis != axis) {
    return std::string(unit->name) + " is " + (unit->axis == 0 ? "an insertion" : "a rotation") + " unit, this script drives the " +
           (axis == 0 ? "insertion" : "rotation") + " axis";
  }
  if (script_axis >= 0 && unit->axis != script_axis) return "mixes insertion and rotation units";
  script_axis = unit->axis;
  s.value = number * unit->to_si;
  if (!parse_duration(item.substr(b + 1), s.duration_us)) return "bad duration (e.g. 500ms, 2s)";
  return {};
}

}  // namespace

Result<HandScript> HandScript::parse(const std::string& text) { return parse(text, -1); }

Result<HandScript> HandScript::parse(const std::string& text, int axis) {
  std::vector<HandSegment> segments;
  size_t start = 0;
  int index = 1;
  int script_axis = -1;  // the axis its units name, once a value has been read
  while (start <= text.size() && !text.empty()) {
    const size_t comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const std::string where = "hand script segment " + std::to_string(index) + " '" + item + "'";
    const size_t a = item.find(':');
    const size_t b = a == std::string::npos ? a : item.find(':', a + 1);
    HandSegment s;
    const std::string mode = item.substr(0, a);
    if (mode == "free" && a != std::string::npos && b == std::string::npos) {
      if (!parse_duration(item.substr(a + 1), s.duration_us)) return Error{where + ": bad duration (e.g. 500ms, 2s)"};
    } else if ((mode == "v" || mode == "f") && b != std::string::npos) {
      s.mode = mode == "v" ? HandMode::kVelocity : HandMode::kForce;
      const std::string problem = read_driven(item, a, b, axis, script_axis, s);
      if (!problem.empty()) return Error{where + ": " + problem};
    } else {
      return Error{where + ": expected v:VALUE:DURATION, f:VALUE:DURATION or free:DURATION"};
    }
    segments.push_back(s);
    if (comma == std::string::npos) break;
    start = comma + 1;
    ++index;
  }
  return HandScript(std::move(segments));
}

HandSegment HandScript::at(uint64_t t_us) const {
  uint64_t start = 0;
  for (const auto& s : segments_) {
    if (t_us < start + s.duration_us) return s;
    start += s.duration_us;
  }
  return HandSegment{};
}

}  // namespace cathbox::emu
