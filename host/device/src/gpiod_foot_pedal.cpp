#include "device/gpiod_foot_pedal.hpp"

#include <gpiod.h>

#include <cerrno>
#include <cstring>

#include "os_error.hpp"

namespace cathbox::device {
namespace {

constexpr const char* kPedalConsumer = "cathbox-pedal";

}  // namespace

Result<std::unique_ptr<GpiodFootPedal>> GpiodFootPedal::open(const PedalConfig& config) {
  gpiod_chip* chip = gpiod_chip_open_lookup(config.chip.c_str());
  if (chip == nullptr) return os_error("open GPIO chip '" + config.chip + "' for the foot pedal");
  gpiod_line* line = gpiod_chip_get_line(chip, config.line);
  if (line == nullptr) {
    gpiod_chip_close(chip);
    return os_error(config.chip + ": no line " + std::to_string(config.line) + " for the foot pedal");
  }
  const int flags = config.active_low ? (GPIOD_LINE_REQUEST_FLAG_ACTIVE_LOW | GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_UP)
                                      : GPIOD_LINE_REQUEST_FLAG_BIAS_PULL_DOWN;
  if (gpiod_line_request_input_flags(line, kPedalConsumer, flags) != 0) {
    gpiod_chip_close(chip);
    return os_error(config.chip + ": request foot pedal line " + std::to_string(config.line));
  }
  return std::unique_ptr<GpiodFootPedal>(new GpiodFootPedal(chip, line, config));
}

GpiodFootPedal::GpiodFootPedal(gpiod_chip* chip, gpiod_line* line, PedalConfig config)
    : chip_(chip), line_(line), config_(std::move(config)) {}

GpiodFootPedal::~GpiodFootPedal() {
  gpiod_line_release(line_);
  gpiod_chip_close(chip_);
}

Result<bool> GpiodFootPedal::read() {
  const int v = gpiod_line_get_value(line_);  // active-low lines read 1 when pulled to ground
  if (v < 0) return os_error(config_.chip + ": read foot pedal line " + std::to_string(config_.line));
  return v == 1;
}

}  // namespace cathbox::device
