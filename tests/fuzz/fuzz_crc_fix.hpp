// Shared by the fuzz targets that take a 64-byte report: a 65th input byte with its low bit
// set asks for a correct CRC, so that the fuzzer also explores the checks behind the CRC
// instead of stopping at it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "protocol/cbx_protocol.h"

// Returns the bytes to use: `input` itself, or `fixed` holding its first 64 bytes with the
// CRC corrected (then `size` becomes 64).
inline const uint8_t* cbx_fuzz_fix_crc(const uint8_t* input, size_t& size, uint8_t (&fixed)[CBX_REPORT_SIZE]) {
  if (size != CBX_REPORT_SIZE + 1 || (input[CBX_REPORT_SIZE] & 1u) == 0u) return input;
  std::memcpy(fixed, input, CBX_REPORT_SIZE);
  cbx_report_finish(fixed);
  size = CBX_REPORT_SIZE;
  return fixed;
}
