#pragma once
// The fluoroscopy foot pedal of a lab rig: a normally-open foot switch read as a GPIO input
// (gpiod_foot_pedal.hpp), or anything else that can say whether it is pressed. Contacts
// bounce for a few milliseconds; PedalDebouncer turns the raw level into presses and releases
// that the session records.
#include <cstdint>
#include <string>

#include "device/result.hpp"

namespace cathbox::device {

class FootPedal {
 public:
  virtual ~FootPedal() = default;
  // The raw contact level now: true = pressed. Never blocks.
  [[nodiscard]] virtual Result<bool> read() = 0;
};

// A level change counts once it has held for `hold_us` (default 5 ms) of the caller's clock.
class PedalDebouncer {
 public:
  explicit PedalDebouncer(std::uint64_t hold_us = 5'000) : hold_us_(hold_us) {}
  // Feeds one raw reading at time now_us (non-decreasing); returns the debounced state.
  bool update(bool raw, std::uint64_t now_us);
  [[nodiscard]] bool pressed() const { return state_; }

 private:
  std::uint64_t hold_us_;
  bool state_ = false;
  bool candidate_ = false;
  std::uint64_t candidate_since_us_ = 0;
};

struct PedalConfig {
  std::string chip = "gpiochip0";  // name, number or /dev path
  unsigned line = 22;
  bool active_low = true;          // switch to ground with the line pulled up (the default wiring)
  // Parses "CHIP:LINE[:active-high|active-low]", e.g. "gpiochip0:22"; errors name the field.
  [[nodiscard]] static Result<PedalConfig> parse(const std::string& text);
};

}  // namespace cathbox::device
