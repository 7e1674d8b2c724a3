#include "emu/hand_script.hpp"

#include <cmath>
#include <cstdlib>

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

}  // namespace

Result<HandScript> HandScript::parse(const std::string& text) {
  std::vector<HandSegment> segments;
  size_t start = 0;
  int index = 1;
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
      char* end = nullptr;
      const std::string value = item.substr(a + 1, b - a - 1);
      s.value = std::strtod(value.c_str(), &end);
      if (value.empty() || *end != '\0' || !std::isfinite(s.value)) return Error{where + ": bad value"};
      if (!parse_duration(item.substr(b + 1), s.duration_us)) return Error{where + ": bad duration (e.g. 500ms, 2s)"};
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
