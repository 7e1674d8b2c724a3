#include "device/gpiod_boot_pins.hpp"

#include <gpiod.h>

#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <thread>

#include "os_error.hpp"

namespace cathbox::device {
namespace {

constexpr const char* kRecoveryConsumer = "cathbox-recovery";

bool parse_line(const std::string& text, unsigned& out) {
  if (text.empty()) return false;
  char* end = nullptr;
  const unsigned long v = std::strtoul(text.c_str(), &end, 10);
  if (*end != '\0' || v > 1023) return false;
  out = static_cast<unsigned>(v);
  return true;
}

}  // namespace

Result<GpioConfig> GpioConfig::parse(const std::string& text) {
  const size_t a = text.find(':');
  const size_t b = a == std::string::npos ? a : text.find(':', a + 1);
  if (a == std::string::npos || b == std::string::npos || a == 0) {
    return make_error(Errc::kBadArgument, "--recover-gpio '" + text + "': expected CHIP:BOOT0_LINE:NRST_LINE, e.g. gpiochip0:17:27");
  }
  GpioConfig config;
  config.chip = text.substr(0, a);
  if (!parse_line(text.substr(a + 1, b - a - 1), config.boot0_line)) {
    return make_error(Errc::kBadArgument, "--recover-gpio '" + text + "': BOOT0 line is not a line number");
  }
  if (!parse_line(text.substr(b + 1), config.nrst_line)) {
    return make_error(Errc::kBadArgument, "--recover-gpio '" + text + "': NRST line is not a line number");
  }
  if (config.boot0_line == config.nrst_line) return make_error(Errc::kBadArgument, "--recover-gpio: BOOT0 and NRST are the same line");
  return config;
}

Result<std::unique_ptr<GpiodBootPins>> GpiodBootPins::open(const GpioConfig& config) {
  gpiod_chip* chip = gpiod_chip_open_lookup(config.chip.c_str());
  if (chip == nullptr) return os_error("open GPIO chip '" + config.chip + "'");
  gpiod_line* boot0 = gpiod_chip_get_line(chip, config.boot0_line);
  gpiod_line* nrst = gpiod_chip_get_line(chip, config.nrst_line);
  if (boot0 == nullptr || nrst == nullptr) {
    gpiod_chip_close(chip);
    return os_error(config.chip + ": no line " + std::to_string(boot0 == nullptr ? config.boot0_line : config.nrst_line));
  }
  if (gpiod_line_request_output(boot0, kRecoveryConsumer, 0) != 0) {
    gpiod_chip_close(chip);
    return os_error(config.chip + ": request BOOT0 line " + std::to_string(config.boot0_line));
  }
  if (gpiod_line_request_output_flags(nrst, kRecoveryConsumer, GPIOD_LINE_REQUEST_FLAG_OPEN_DRAIN, 1) != 0) {
    gpiod_line_release(boot0);
    gpiod_chip_close(chip);
    return os_error(config.chip + ": request NRST line " + std::to_string(config.nrst_line));
  }
  return std::unique_ptr<GpiodBootPins>(new GpiodBootPins(chip, boot0, nrst, config));
}

GpiodBootPins::GpiodBootPins(gpiod_chip* chip, gpiod_line* boot0, gpiod_line* nrst, GpioConfig config)
    : chip_(chip), boot0_(boot0), nrst_(nrst), config_(std::move(config)) {}

GpiodBootPins::~GpiodBootPins() {
  gpiod_line_release(boot0_);
  gpiod_line_release(nrst_);
  gpiod_chip_close(chip_);
}

Status GpiodBootPins::set_boot0(bool high) {
  if (gpiod_line_set_value(boot0_, high ? 1 : 0) != 0) return os_error("set BOOT0");
  return Ok{};
}

Status GpiodBootPins::set_reset(bool asserted) {
  if (gpiod_line_set_value(nrst_, asserted ? 0 : 1) != 0) return os_error("set NRST");
  return Ok{};
}

void GpiodBootPins::delay(uint64_t us) { std::this_thread::sleep_for(std::chrono::microseconds(us)); }

}  // namespace cathbox::device
