// libFuzzer target for one protocol decoder, chosen at compile time (CBX_FUZZ_KIND).
// Property: never crash; a report that decodes re-encodes to a report that decodes to the
// same value and re-encodes to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "protocol/cbx_command_report.h"
#include "protocol/cbx_crc16.h"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_state_report.h"

#define CBX_CAT2(a, b) a##b
#define CBX_CAT(a, b) CBX_CAT2(a, b)
#define CBX_DECODE CBX_CAT(CBX_CAT(cbx_, CBX_FUZZ_KIND), _decode)
#define CBX_ENCODE CBX_CAT(CBX_CAT(cbx_, CBX_FUZZ_KIND), _encode)

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* input, size_t size) {
  // A 65th byte with its low bit set asks for a correct CRC, so that the fuzzer also explores
  // the range checks behind the CRC instead of stopping at it.
  uint8_t fixed[CBX_REPORT_SIZE];
  const uint8_t* data = input;
  if (size == CBX_REPORT_SIZE + 1 && (input[CBX_REPORT_SIZE] & 1u) != 0u) {
    std::memcpy(fixed, input, CBX_REPORT_SIZE);
    const uint16_t crc = cbx_crc16(fixed, CBX_CRC_OFFSET);
    fixed[CBX_CRC_OFFSET] = static_cast<uint8_t>(crc & 0xFFu);
    fixed[CBX_CRC_OFFSET + 1] = static_cast<uint8_t>(crc >> 8);
    data = fixed;
    size = CBX_REPORT_SIZE;
  }
  CBX_FUZZ_TYPE first;
  if (CBX_DECODE(data, size, &first) != CBX_OK) return 0;
  uint8_t once[CBX_REPORT_SIZE];
  if (CBX_ENCODE(&first, once) != CBX_OK) std::abort();
  CBX_FUZZ_TYPE second;
  if (CBX_DECODE(once, sizeof once, &second) != CBX_OK) std::abort();
  uint8_t twice[CBX_REPORT_SIZE];
  if (CBX_ENCODE(&second, twice) != CBX_OK) std::abort();
  if (std::memcmp(once, twice, sizeof once) != 0) std::abort();
  // Everything but reserved bytes is carried: the payload fields of the input survive.
  if (std::memcmp(once, data, 8) != 0) std::abort();
  return 0;
}
