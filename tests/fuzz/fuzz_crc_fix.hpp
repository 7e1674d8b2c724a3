// Shared by the fuzz targets that take a 64-byte report: a 65th input byte with its low bit
// set asks for a correct CRC, so that the fuzzer also explores the checks behind the CRC
// instead of stopping at it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "protocol/cbx_crc16.h"
#include "protocol/cbx_protocol.h"

// Returns the bytes to use: `input` itself, or `fixed` holding its first 64 bytes with the
// CRC corrected (then `size` becomes 64).
inline const uint8_t* cbx_fuzz_fix_crc(const uint8_t* input, size_t& size, uint8_t (&fixed)[CBX_REPORT_SIZE]) {
  if (size != CBX_REPORT_SIZE + 1 || (input[CBX_REPORT_SIZE] & 1u) == 0u) return input;
  std::memcpy(fixed, input, CBX_REPORT_SIZE);
  const uint16_t crc = cbx_crc16(fixed, CBX_CRC_OFFSET);
  fixed[CBX_CRC_OFFSET] = static_cast<uint8_t>(crc & 0xFFu);
  fixed[CBX_CRC_OFFSET + 1] = static_cast<uint8_t>(crc >> 8);
  size = CBX_REPORT_SIZE;
  return fixed;
}
