#pragma once
// The STM32F411's 512 KiB internal flash as the ROM bootloader sees it: sectors of 4 x 16 KiB,
// 1 x 64 KiB and 3 x 128 KiB at 0x08000000. Erased bytes read 0xFF; programming needs erased
// bytes (a write over programmed bytes fails, as the flash controller's sequence check does).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "protocol/cbx_image_info.h"

namespace cathbox::emu {

struct FlashSector {
  uint32_t address;
  uint32_t size;
  uint32_t erase_ms;  // typical sector erase time (datasheet, x32 parallelism)
};

class FlashMemory {
 public:
  static constexpr uint32_t kBase = 0x08000000u;
  FlashMemory();

  [[nodiscard]] const std::vector<FlashSector>& sectors() const { return sectors_; }
  [[nodiscard]] uint32_t size() const { return static_cast<uint32_t>(bytes_.size()); }
  // The DfuSe alternate-setting name describing this layout.
  [[nodiscard]] std::string layout_name() const;
  // Index of the sector holding address, or -1.
  [[nodiscard]] int sector_at(uint32_t address) const;
  [[nodiscard]] bool contains(uint32_t address, size_t length) const;

  void erase_sector(int index);
  // False (nothing written) when out of range or a target byte is not erased.
  [[nodiscard]] bool program(uint32_t address, std::span<const uint8_t> data);
  // False when out of range.
  [[nodiscard]] bool read(uint32_t address, std::span<uint8_t> out) const;
  // True when the vector table looks bootable: stack pointer in SRAM, reset vector a Thumb
  // address in flash.
  [[nodiscard]] bool application_valid() const;
  // The image info block of the application (protocol/cbx_image_info.h, at
  // CBX_IMAGE_INFO_OFFSET), when there is a valid one.
  [[nodiscard]] std::optional<cbx_image_info> image_info() const;
  // Writes bytes directly (factory programming, tests).
  void load(uint32_t address, std::span<const uint8_t> data);

 private:
  std::vector<FlashSector> sectors_;
  std::vector<uint8_t> bytes_;
};

}  // namespace cathbox::emu
