#pragma once
// A DfuSe file (.dfu, ST UM0391, as `cathbox flash pack` writes it) read into the bytes of the
// STM32F411's internal flash, for `cathbox-emu --image FILE.dfu`. Checked: the prefix ("DfuSe",
// version 1, DFUImageSize), each target ("Target", alternate setting 0 = internal flash, its
// size), each element (address and size inside the 512 KiB flash at 0x08000000, no overlap), and
// the suffix (bcdDFU 0x011A, "UFD", length 16, CRC-32 over everything before it). Errors are one
// line: "NAME: byte OFFSET: what".
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "emu/result.hpp"

namespace cathbox::emu {

struct DfuseFlashImage {
  std::vector<uint8_t> flash;  // from 0x08000000 to the end of the last element; gaps read 0xFF
  uint16_t bcd_device = 0;     // the suffix's firmware version (0xMMmm)
  uint32_t elements = 0;
};

[[nodiscard]] Result<DfuseFlashImage> read_dfuse(std::span<const uint8_t> file, const std::string& name);

// True when the name ends in ".dfu" (any case): cathbox-emu reads such a file as DfuSe.
[[nodiscard]] bool is_dfuse_name(const std::string& name);

}  // namespace cathbox::emu
