#include "session/record_format.hpp"

#include <zlib.h>

#include <cstring>

#include "base/bit_cast.hpp"
#include "base/byte_order.hpp"

namespace cathbox::session::record {

const char* end_reason_name(EndReason reason) {
  switch (reason) {
    case EndReason::kStopped: return "stopped";
    case EndReason::kTargetReached: return "target reached";
    case EndReason::kHandFinished: return "hand finished";
    case EndReason::kEndedByUser: return "ended by the trainee";
    case EndReason::kTimeLimit: return "time limit";
  }
  return "unknown";
}

std::uint32_t crc32(std::span<const std::uint8_t> a, std::span<const std::uint8_t> b) {
  uLong c = ::crc32(0L, Z_NULL, 0);
  // zlib takes uInt lengths; blocks are at most 16 MiB.
  if (!a.empty()) c = ::crc32(c, a.data(), static_cast<uInt>(a.size()));
  if (!b.empty()) c = ::crc32(c, b.data(), static_cast<uInt>(b.size()));
  return static_cast<std::uint32_t>(c);
}

namespace {

// Appends n bytes to out and returns where they start, for the base::put_le writers.
std::uint8_t* grow(std::vector<std::uint8_t>& out, std::size_t n) {
  out.resize(out.size() + n);
  return out.data() + out.size() - n;
}

}  // namespace

void ByteWriter::u16(std::uint16_t v) { base::put_le(grow(out_, 2), v); }
void ByteWriter::u32(std::uint32_t v) { base::put_le(grow(out_, 4), v); }
void ByteWriter::u64(std::uint64_t v) { base::put_le(grow(out_, 8), v); }

void ByteWriter::f64(double v) { u64(base::bit_cast<std::uint64_t>(v)); }

void ByteWriter::varint(std::uint64_t v) {
  while (v >= 0x80) {
    out_.push_back(static_cast<std::uint8_t>(v | 0x80));
    v >>= 7;
  }
  out_.push_back(static_cast<std::uint8_t>(v));
}

void ByteWriter::field(std::uint32_t tag, std::span<const std::uint8_t> b) {
  varint(tag);
  varint(b.size());
  bytes(b);
}

void ByteWriter::field_text(std::uint32_t tag, std::string_view s) {
  field(tag, {reinterpret_cast<const std::uint8_t*>(s.data()), s.size()});
}

void ByteWriter::field_u64(std::uint32_t tag, std::uint64_t v) {
  varint(tag);
  varint(8);
  u64(v);
}

void ByteWriter::field_f64(std::uint32_t tag, double v) { field_u64(tag, base::bit_cast<std::uint64_t>(v)); }

bool ByteReader::u8(std::uint8_t& v) {
  if (left() < 1) return false;
  v = in_[pos_++];
  return true;
}

template <class T>
bool ByteReader::fixed(T& v) {
  if (left() < sizeof(T)) return false;
  v = base::get_le<T>(in_.data() + pos_);
  pos_ += sizeof(T);
  return true;
}

bool ByteReader::u16(std::uint16_t& v) { return fixed(v); }
bool ByteReader::u32(std::uint32_t& v) { return fixed(v); }
bool ByteReader::u64(std::uint64_t& v) { return fixed(v); }

bool ByteReader::f64(double& v) {
  std::uint64_t bits = 0;
  if (!u64(bits)) return false;
  v = base::bit_cast<double>(bits);
  return true;
}

bool ByteReader::varint(std::uint64_t& v) {
  v = 0;
  for (int shift = 0; shift < 64; shift += 7) {
    std::uint8_t b = 0;
    if (!u8(b)) return false;
    if (shift == 63 && b > 1) return false;  // more than 64 bits
    v |= static_cast<std::uint64_t>(b & 0x7F) << shift;
    if ((b & 0x80) == 0) return true;
  }
  return false;
}

bool ByteReader::zigzag(std::int64_t& v) {
  std::uint64_t u = 0;
  if (!varint(u)) return false;
  v = static_cast<std::int64_t>((u >> 1) ^ (~(u & 1) + 1));
  return true;
}

bool ByteReader::bytes(std::size_t n, std::span<const std::uint8_t>& out) {
  if (left() < n) return false;
  out = in_.subspan(pos_, n);
  pos_ += n;
  return true;
}

}  // namespace cathbox::session::record
