// libFuzzer target for the emulator socket frame decoder: never crash; whatever decodes
// re-encodes to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "protocol/cbx_emu_frame.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  cbx_emu_frame frame;
  if (cbx_emu_frame_decode(data, size, &frame) != CBX_OK) return 0;
  std::vector<uint8_t> out(CBX_EMU_FRAME_MAX);
  const int n = cbx_emu_frame_encode(&frame, out.data(), out.size());
  if (n < 0 || static_cast<size_t>(n) != size || std::memcmp(out.data(), data, size) != 0) std::abort();
  return 0;
}
