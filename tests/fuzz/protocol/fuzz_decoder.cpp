// libFuzzer target for one protocol decoder, chosen at compile time (CBX_FUZZ_KIND).
// Property: never crash; a report that decodes re-encodes to a report that decodes to the
// same value and re-encodes to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "../fuzz_crc_fix.hpp"
#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_state_report.h"

#define CBX_CAT2(a, b) a##b
#define CBX_CAT(a, b) CBX_CAT2(a, b)
#define CBX_DECODE CBX_CAT(CBX_CAT(cbx_, CBX_FUZZ_KIND), _decode)
#define CBX_ENCODE CBX_CAT(CBX_CAT(cbx_, CBX_FUZZ_KIND), _encode)

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* input, size_t size) {
  uint8_t fixed[CBX_REPORT_SIZE];
  const uint8_t* data = cbx_fuzz_fix_crc(input, size, fixed);
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
