#pragma once
// Flashing a Cathbox image into the STM32 ROM bootloader: every check first (image target,
// size, CRC, version, vector table, and the bootloader's announced memory layout), then erase,
// download, verify by upload, leave. Nothing is erased unless every check passed.
#include <cstdint>
#include <functional>
#include <string>

#include "device/control_transfer.hpp"
#include "device/dfu_file.hpp"
#include "device/result.hpp"

namespace cathbox::device {

// What a Cathbox image must be built for.
struct FirmwareTarget {
  std::string name = "cathbox stm32f411";  // DfuSe target name
  uint32_t flash_base = 0x08000000u;
  uint32_t flash_size = 512u * 1024u;
  uint32_t ram_base = 0x20000000u;
  uint32_t ram_size = 128u * 1024u;
  unsigned firmware_major = 1;  // = protocol major the host speaks
};

struct FlashReport {
  size_t bytes_written = 0;
  size_t sectors_erased = 0;
  size_t bytes_verified = 0;
};

class Flasher {
 public:
  using Progress = std::function<void(const std::string& step, size_t done, size_t total)>;

  // Offline checks of an image against a target (no device needed). One clear line on failure.
  [[nodiscard]] static Status check_image(const DfuImage& image, const FirmwareTarget& target);
  // Flashes `image` through a bootloader reached over `usb`. `progress` may be empty.
  [[nodiscard]] static Result<FlashReport> flash(ControlTransfer& usb, const DfuImage& image,
                                                 const FirmwareTarget& target, const Progress& progress);
  // "1.2" from a bcdDevice.
  [[nodiscard]] static std::string version_text(uint16_t bcd_device);
};

}  // namespace cathbox::device
