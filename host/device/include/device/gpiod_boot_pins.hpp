#pragma once
// BootPins on a Linux GPIO character device through libgpiod 1.6 (e.g. a Raspberry Pi on the
// lab rig: chip "gpiochip0", BOOT0 on line 17, NRST on line 27, wired to the Black Pill).
#include <memory>
#include <string>

#include "device/boot_pins.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace cathbox::device {

struct GpioConfig {
  std::string chip = "gpiochip0";  // name, number or /dev path (gpiod_chip_open_lookup)
  unsigned boot0_line = 17;
  unsigned nrst_line = 27;
  // Parses "CHIP:BOOT0:NRST", e.g. "gpiochip0:17:27"; errors name the bad field.
  [[nodiscard]] static Result<GpioConfig> parse(const std::string& text);
};

class GpiodBootPins final : public BootPins {
 public:
  // Requests both lines as outputs (BOOT0 low, NRST released; NRST open drain).
  [[nodiscard]] static Result<std::unique_ptr<GpiodBootPins>> open(const GpioConfig& config);
  ~GpiodBootPins() override;
  GpiodBootPins(const GpiodBootPins&) = delete;
  GpiodBootPins& operator=(const GpiodBootPins&) = delete;

  [[nodiscard]] Status set_boot0(bool high) override;
  [[nodiscard]] Status set_reset(bool asserted) override;
  void delay(uint64_t us) override;

 private:
  GpiodBootPins(gpiod_chip* chip, gpiod_line* boot0, gpiod_line* nrst, GpioConfig config);
  gpiod_chip* chip_;
  gpiod_line* boot0_;
  gpiod_line* nrst_;
  GpioConfig config_;
};

}  // namespace cathbox::device
