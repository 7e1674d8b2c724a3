#include "device/foot_pedal.hpp"

#include <cstdlib>

namespace cathbox::device {

bool PedalDebouncer::update(bool raw, std::uint64_t now_us) {
  if (raw == state_) {
    candidate_ = state_;
    return state_;
  }
  if (raw != candidate_) {
    candidate_ = raw;
    candidate_since_us_ = now_us;
  }
  if (now_us - candidate_since_us_ >= hold_us_) state_ = raw;
  return state_;
}

Result<PedalConfig> PedalConfig::parse(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return make_error(Errc::kBadArgument, "--pedal-gpio '" + text + "': " + why);
  };
  const std::size_t a = text.find(':');
  if (a == std::string::npos || a == 0) return bad("expected CHIP:LINE[:active-high|active-low], e.g. gpiochip0:22");
  PedalConfig config;
  config.chip = text.substr(0, a);
  const std::size_t b = text.find(':', a + 1);
  const std::string line = text.substr(a + 1, b == std::string::npos ? std::string::npos : b - a - 1);
  char* end = nullptr;
  const unsigned long v = std::strtoul(line.c_str(), &end, 10);
  if (line.empty() || *end != '\0' || v > 1023) return bad("LINE is not a line number");
  config.line = static_cast<unsigned>(v);
  if (b != std::string::npos) {
    const std::string polarity = text.substr(b + 1);
    if (polarity == "active-high") {
      config.active_low = false;
    } else if (polarity != "active-low") {
      return bad("polarity must be active-high or active-low");
    }
  }
  return config;
}

}  // namespace cathbox::device
