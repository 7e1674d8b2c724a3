// libFuzzer target for the session record reader: never crash, never hang; every problem is
// one line "fuzz.cbxrec: byte N: what". The first input byte picks the mode: with its low bit
// set, the file header's version is set to this build's and its and every block's CRC-32 are
// corrected first (walking the block headers: record_crc_fix.hpp), so that the fuzzer also
// explores the header fields, the tick entries and the decompression behind them instead of
// stopping at them.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "session/record_format.hpp"
#include "session/record_reader.hpp"
#include "record_crc_fix.hpp"

namespace {

void check_line(const std::string& error) {
  if (error.empty()) return;
  if (error.rfind("fuzz.cbxrec: byte ", 0) != 0 || error.find('\n') != std::string::npos) {
    std::fprintf(stderr, "bad error line: %s\n", error.c_str());
    std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  std::vector<uint8_t> bytes(data + 1, data + size);
  if ((data[0] & 1u) != 0u) fix_crcs(bytes);
  auto opened = cathbox::session::RecordReader::from_bytes(std::move(bytes), "fuzz.cbxrec");
  if (!opened) {
    check_line(opened.error().message);
    return 0;
  }
  auto& reader = *opened;
  cathbox::session::TickRecord tick;
  std::int64_t n = 0;
  while (reader->next(tick)) {
    if (tick.tick != n++) std::abort();  // ticks are delivered in order, none skipped
  }
  check_line(reader->error());
  return 0;
}
