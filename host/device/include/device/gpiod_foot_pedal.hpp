#pragma once
// FootPedal on a Linux GPIO character device through libgpiod 1.6: the line requested as an
// input with the bias the wiring needs (pull-up for a switch to ground, active low), read
// without blocking. Verified only against the error paths on machines without GPIO.
#include <memory>

#include "device/foot_pedal.hpp"

struct gpiod_chip;
struct gpiod_line;

namespace cathbox::device {

class GpiodFootPedal final : public FootPedal {
 public:
  [[nodiscard]] static Result<std::unique_ptr<GpiodFootPedal>> open(const PedalConfig& config);
  ~GpiodFootPedal() override;
  GpiodFootPedal(const GpiodFootPedal&) = delete;
  GpiodFootPedal& operator=(const GpiodFootPedal&) = delete;

  [[nodiscard]] Result<bool> read() override;

 private:
  GpiodFootPedal(gpiod_chip* chip, gpiod_line* line, PedalConfig config);
  gpiod_chip* chip_;
  gpiod_line* line_;
  PedalConfig config_;
};

}  // namespace cathbox::device
