// Shared by the fuzz targets that take a session record: sets the file header's format version
// to this build's and corrects its CRC-32 and every block's (walking the block headers), so that
// the fuzzer also explores the header fields, the tick entries and the decompression behind the
// version and the CRCs instead of stopping at them: the seed records, written at older formats,
// stay useful past each bump of the format (the other mode still meets the version check).
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "protocol/cbx_bytes.h"
#include "session/record_format.hpp"

namespace {

inline void fix_crcs(std::vector<uint8_t>& b) {
  using namespace cathbox::session::record;
  if (b.size() < kFileHeaderSize) return;
  cbx_put_u16(b.data() + 8, kFormatVersion);
  cbx_put_u32(b.data() + 12, crc32(std::span<const uint8_t>(b).first(12)));
  size_t pos = kFileHeaderSize;
  while (pos + kBlockHeaderSize <= b.size()) {
    const uint32_t stored = cbx_get_u32(b.data() + pos + 4);
    if (stored > b.size() - pos - kBlockHeaderSize) break;
    const std::span<const uint8_t> all(b);
    cbx_put_u32(b.data() + pos + 12, crc32(all.subspan(pos, 12), all.subspan(pos + kBlockHeaderSize, stored)));
    pos += kBlockHeaderSize + stored;
  }
}

}  // namespace
