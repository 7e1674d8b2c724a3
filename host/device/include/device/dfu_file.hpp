#pragma once
// DfuSe firmware files (.dfu, ST UM0391): prefix "DfuSe", targets with named images made of
// elements (address + bytes), and the DFU 1.1 suffix (bcdDevice, VID, PID, "UFD", CRC-32).
// Cathbox convention (host/device/README.md): one target, alternate setting 0, named
// "cathbox stm32f411"; bcdDevice = firmware major.minor (major = protocol major).
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "device/result.hpp"

namespace cathbox::device {

struct DfuElement {
  uint32_t address = 0;
  std::vector<uint8_t> data;
};

struct DfuImage {
  uint16_t bcd_device = 0;  // firmware version, 0xMMmm (major, minor) in BCD
  uint16_t vid = 0;
  uint16_t pid = 0;
  uint8_t alt_setting = 0;
  std::string target_name;
  std::vector<DfuElement> elements;
  [[nodiscard]] size_t total_bytes() const;
};

class DfuFile {
 public:
  // Parses a whole .dfu file; errors name the file, the field and the byte offset.
  [[nodiscard]] static Result<DfuImage> parse(std::span<const uint8_t> bytes, const std::string& name);
  [[nodiscard]] static Result<DfuImage> load(const std::string& path);
  // Serialises an image (one target) with a correct suffix CRC.
  [[nodiscard]] static std::vector<uint8_t> write(const DfuImage& image);
  // The suffix CRC: CRC-32 (reflected 0x04C11DB7, initial 0xFFFFFFFF, no final XOR).
  [[nodiscard]] static uint32_t crc32(std::span<const uint8_t> bytes);
};

}  // namespace cathbox::device
