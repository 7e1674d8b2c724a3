#include "session/record_reader.hpp"

#include <zstd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <limits>

#include "base/text_tokens.hpp"

namespace cathbox::session {
namespace {

using record::BlockType;
using record::ByteReader;
using record::EntryKind;

std::string hex(std::uint64_t v) {
  char buf[24];
  std::snprintf(buf, sizeof buf, "0x%02llx", static_cast<unsigned long long>(v));
  return buf;
}

}  // namespace

RecordReader::~RecordReader() {
  if (file_ != nullptr) std::fclose(file_);
  ZSTD_freeDCtx(static_cast<ZSTD_DCtx*>(dctx_));
}

base::Result<std::unique_ptr<RecordReader>> RecordReader::open(const std::string& path) {
  std::unique_ptr<RecordReader> r(new RecordReader(path));
  r->file_ = std::fopen(path.c_str(), "rb");
  if (r->file_ == nullptr) return base::Error{path + ": cannot open: " + std::strerror(errno)};
  if (!r->start()) return base::Error{r->error_};
  return r;
}

base::Result<std::unique_ptr<RecordReader>> RecordReader::from_bytes(std::vector<std::uint8_t> bytes,
                                                                     const std::string& name) {
  std::unique_ptr<RecordReader> r(new RecordReader(name));
  r->memory_ = std::move(bytes);
  r->from_memory_ = true;
  if (!r->start()) return base::Error{r->error_};
  return r;
}

bool RecordReader::fail(std::uint64_t byte, const std::string& what) {
  if (error_.empty()) {
    // One line, whatever the record's text fields hold: bytes outside printable ASCII as \xNN.
    error_ = name_ + ": byte " + std::to_string(byte) + ": " + base::text::escape_bytes(what);
  }
  stopped_ = true;
  return false;
}

bool RecordReader::read_exact(std::uint8_t* out, std::size_t n, std::size_t& got) {
  if (from_memory_) {
    const std::size_t left = memory_.size() - static_cast<std::size_t>(std::min<std::uint64_t>(file_pos_, memory_.size()));
    got = std::min(n, left);
    if (got > 0) std::memcpy(out, memory_.data() + file_pos_, got);  // out may be null when n is 0
  } else {
    got = std::fread(out, 1, n, file_);
  }
  file_pos_ += got;
  return got == n;
}

bool RecordReader::start() {
  dctx_ = ZSTD_createDCtx();
  std::array<std::uint8_t, record::kFileHeaderSize> head{};
  std::size_t got = 0;
  if (!read_exact(head.data(), head.size(), got)) {
    return fail(got, "not a cathbox record: " + std::to_string(got) + " bytes, shorter than the 16-byte file header");
  }
  if (!std::equal(record::kMagic.begin(), record::kMagic.end(), head.begin())) {
    return fail(0, "not a cathbox record (the file does not start with \"CBXREC\\r\\n\")");
  }
  ByteReader r{std::span<const std::uint8_t>(head).subspan(8)};
  std::uint16_t version = 0;
  std::uint16_t reserved = 0;
  std::uint32_t crc = 0;
  (void)r.u16(version);
  (void)r.u16(reserved);
  (void)r.u32(crc);
  if (crc != record::crc32(std::span(head).first(12))) return fail(12, "file header CRC mismatch");
  if (version != record::kFormatVersion) {
    return fail(8, "record format version " + std::to_string(version) + ", this build reads version " +
                       std::to_string(record::kFormatVersion));
  }
  if (reserved != 0) return fail(10, "reserved bytes are not zero");
  BlockType type{};
  bool eof = false;
  if (!read_block(type, eof)) return eof ? fail(file_pos_, "no header block") : false;
  if (type != BlockType::kHeader) return fail(block_at_, "the first block is not the header block");
  std::string what;
  std::size_t offset = 0;
  if (!decode_header(raw_, header_, what, offset)) {
    return fail(block_at_, what + " (offset " + std::to_string(offset) + " of the header block's data)");
  }
  return true;
}

bool RecordReader::read_block(BlockType& type, bool& eof) {
  eof = false;
  block_at_ = file_pos_;
  std::array<std::uint8_t, record::kBlockHeaderSize> head{};
  std::size_t got = 0;
  if (!read_exact(head.data(), head.size(), got)) {
    if (got == 0) {
      eof = true;
      return false;
    }
    return fail(block_at_, "truncated block header (" + std::to_string(got) + " of 16 bytes)");
  }
  ByteReader r(head);
  std::uint8_t t = 0;
  std::uint8_t compression = 0;
  std::uint16_t reserved = 0;
  std::uint32_t stored = 0;
  std::uint32_t raw = 0;
  std::uint32_t crc = 0;
  (void)(r.u8(t) && r.u8(compression) && r.u16(reserved) && r.u32(stored) && r.u32(raw) && r.u32(crc));
  if (t != 'H' && t != 'T' && t != 'E') return fail(block_at_, "unknown block type " + hex(t));
  if (compression > 1) return fail(block_at_ + 1, "unknown compression " + std::to_string(compression));
  if (reserved != 0) return fail(block_at_ + 2, "reserved bytes are not zero");
  if (stored > record::kMaxBlockBytes || raw > record::kMaxBlockBytes) {
    return fail(block_at_ + 4, "block of " + std::to_string(std::max(stored, raw)) + " bytes beyond the 16 MiB limit");
  }
  if (compression == 0 && stored != raw) return fail(block_at_ + 4, "uncompressed block with two different lengths");
  stored_.resize(stored);
  if (!read_exact(stored_.data(), stored, got)) {
    return fail(block_at_, "truncated block: " + std::to_string(got) + " of " + std::to_string(stored) + " bytes");
  }
  if (crc != record::crc32(std::span(head).first(12), stored_)) return fail(block_at_, "block CRC mismatch");
  raw_.resize(raw);
  if (compression == 0) {
    raw_ = stored_;
  } else {
    const std::size_t n = ZSTD_decompressDCtx(static_cast<ZSTD_DCtx*>(dctx_), raw_.data(), raw_.size(), stored_.data(),
                                              stored_.size());
    if (ZSTD_isError(n)) return fail(block_at_, std::string("zstd: ") + ZSTD_getErrorName(n));
    if (n != raw) return fail(block_at_, "block decompresses to " + std::to_string(n) + " bytes, not " + std::to_string(raw));
  }
  ++blocks_;
  type = static_cast<BlockType>(t);
  return true;
}

bool RecordReader::parse_end(std::uint64_t at) {
  RecordEnd e;
  ByteReader r(raw_);
  while (!r.done()) {
    const std::size_t field_at = r.position();
    std::uint64_t tag = 0;
    std::uint64_t len = 0;
    std::span<const std::uint8_t> v;
    if (!r.varint(tag) || !r.varint(len) || len > r.left() || !r.bytes(len, v)) {
      return fail(at, "end block: a field runs past its end (offset " + std::to_string(field_at) + ")");
    }
    ByteReader fv(v);
    std::uint64_t u = 0;
    switch (static_cast<record::EndTag>(tag)) {
      case record::EndTag::kReason:
        if (v.size() != 1 || v[0] > 4) return fail(at, "end block: unknown end reason");
        e.reason = static_cast<record::EndReason>(v[0]);
        break;
      case record::EndTag::kReasonText: e.text.assign(reinterpret_cast<const char*>(v.data()), v.size()); break;
      case record::EndTag::kTicks:
        if (v.size() != 8 || !fv.u64(u)) return fail(at, "end block: tick count is not 8 bytes");
        e.ticks = static_cast<std::int64_t>(u);
        break;
      case record::EndTag::kEndUnix_us:
        if (v.size() != 8 || !fv.u64(u)) return fail(at, "end block: end time is not 8 bytes");
        e.end_unix_us = static_cast<std::int64_t>(u);
        break;
      case record::EndTag::kHapticDropped:
        if (v.size() != 8 || !fv.u64(u) || u > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max())) {
          return fail(at, "end block: dropped haptic ticks are not an 8-byte count");
        }
        e.haptic_dropped_ticks = static_cast<std::int64_t>(u);
        break;
      default:
        if (!(tag >= 64 && tag < 128)) return fail(at, "end block: unknown field " + std::to_string(tag));
    }
  }
  if (e.ticks != next_tick_) {
    return fail(at, "end block says " + std::to_string(e.ticks) + " ticks, the record holds " + std::to_string(next_tick_));
  }
  end_ = std::move(e);
  return true;
}

bool RecordReader::entry_error(const std::string& what) {
  return fail(block_at_, "tick " + std::to_string(next_tick_) + ", offset " + std::to_string(pos_) +
                             " of the block's data: " + what);
}

bool RecordReader::next(TickRecord& out) {
  if (stopped_) return false;
  while (block_left_ == 0) {
    BlockType type{};
    bool eof = false;
    if (!read_block(type, eof)) {
      stopped_ = true;  // a clean end of a record without an end block, or an error
      return false;
    }
    if (type == BlockType::kHeader) return fail(block_at_, "a second header block");
    if (type == BlockType::kEnd) {
      if (!parse_end(block_at_)) return false;
      std::uint8_t extra = 0;
      std::size_t got = 0;
      if (read_exact(&extra, 1, got) || got > 0) return fail(file_pos_ - got, "data after the end block");
      stopped_ = true;
      return false;
    }
    ByteReader r(raw_);
    std::uint64_t first = 0;
    std::uint32_t count = 0;
    if (!r.u64(first) || !r.u32(count)) return fail(block_at_, "ticks block shorter than its 12-byte start");
    if (first != static_cast<std::uint64_t>(next_tick_)) {
      return fail(block_at_, "ticks block starts at tick " + std::to_string(first) + ", expected " + std::to_string(next_tick_));
    }
    if (count == 0) return fail(block_at_, "ticks block with no ticks");
    pos_ = r.position();
    block_left_ = count;
  }
  if (!decode_tick(out)) return false;
  --block_left_;
  ++next_tick_;
  if (block_left_ == 0 && pos_ != raw_.size()) {
    return fail(block_at_, std::to_string(raw_.size() - pos_) + " bytes after the block's last tick");
  }
  return true;
}

bool RecordReader::decode_tick(TickRecord& out) {
  out.tick = next_tick_;
  out.control_count = 0;
  out.event_count = 0;
  out.state_hash.reset();
  out.box_changed = false;
  ByteReader r{std::span<const std::uint8_t>(raw_).subspan(pos_)};
  for (;;) {
    const std::size_t at = r.position();
    // The problem named at the entry's offset in the block (pos_ stays at the tick's start).
    auto err = [&](const std::string& what) {
      const std::size_t saved = pos_;
      pos_ += at;
      entry_error(what);
      pos_ = saved;
      return false;
    };
    std::uint64_t kind = 0;
    if (!r.varint(kind)) return err("the tick runs past the end of the block");
    if (kind == static_cast<std::uint64_t>(EntryKind::kEndOfTick)) break;
    std::uint64_t length = 0;
    std::span<const std::uint8_t> payload;
    if (!r.varint(length) || length > r.left() || !r.bytes(length, payload)) {
      return err("entry kind " + std::to_string(kind) + " runs past the end of the block");
    }
    if (std::string problem = decode_entry(kind, payload, out); !problem.empty()) return err(problem);
  }
  pos_ += r.position();
  out.tools = tools_;
  out.box = box_;
  return true;
}

std::string RecordReader::decode_entry(std::uint64_t kind, std::span<const std::uint8_t> payload, TickRecord& out) {
  ByteReader p(payload);
  std::string problem;
  switch (kind) {
    case static_cast<std::uint64_t>(EntryKind::kTools): problem = decode_tools(p); break;
    case static_cast<std::uint64_t>(EntryKind::kStateHash): {
      std::uint64_t h = 0;
      if (payload.size() != 8 || !p.u64(h)) return "state hash entry is not 8 bytes";
      out.state_hash = h;
      break;
    }
    case static_cast<std::uint64_t>(EntryKind::kBoxStatus): {
      std::uint8_t flags = 0;
      std::uint16_t faults = 0;
      if (payload.size() != 3 || !p.u8(flags) || !p.u16(faults) || flags > 3) return "bad box status entry";
      box_ = {(flags & 1) != 0, (flags & 2) != 0, faults};
      out.box_changed = true;
      break;
    }
    case static_cast<std::uint64_t>(EntryKind::kEvent): {
      std::uint8_t code = 0;
      if (payload.size() != 1 || !p.u8(code) || code != static_cast<std::uint8_t>(record::EventCode::kTargetReached)) {
        return "bad event entry";
      }
      if (out.event_count == TickRecord::kMaxEvents) return "more than 8 events in one tick";
      out.events[out.event_count++] = static_cast<record::EventCode>(code);
      break;
    }
    default: return decode_control(kind, payload, out);
  }
  if (!problem.empty()) return problem;
  if (!p.done()) return "entry kind " + std::to_string(kind) + " has " + std::to_string(p.left()) + " bytes left over";
  return {};
}

std::string RecordReader::decode_tools(ByteReader& p) {
  const std::size_t tool_count = header_.tools.size();
  std::uint16_t mask = 0;
  if (!p.u16(mask)) return "tools entry shorter than its 2-byte mask";
  for (std::size_t t = 0; t < 4 * sizeof(mask); ++t) {  // every bit pair of the mask: a tool past the record's is refused
    for (std::size_t axis = 0; axis < 2; ++axis) {
      if ((mask & (1u << (2 * t + axis))) == 0) continue;
      if (t >= tool_count) return "tools entry moves tool " + std::to_string(t) + ", the record has " + std::to_string(tool_count);
      std::int64_t delta = 0;
      if (!p.zigzag(delta)) return "tools entry: a delta runs past the entry";
      std::int64_t& v = axis == 0 ? tools_[t].insertion_um : tools_[t].rotation_urad;
      if (__builtin_add_overflow(v, delta, &v)) return "tools entry: position overflows 64 bits";
    }
  }
  return {};
}

std::string RecordReader::decode_control(std::uint64_t kind, std::span<const std::uint8_t> payload, TickRecord& out) {
  if (kind > 0xFFFF || !known_control_kind(static_cast<std::uint16_t>(kind))) {
    return "unknown kind " + std::to_string(kind) + " (a newer record? this build knows 1-4 and controls " + known_control_kinds() + ")";
  }
  if (payload.size() > Control::kMaxPayload) return "control of " + std::to_string(payload.size()) + " bytes (at most 32)";
  if (out.control_count == TickRecord::kMaxControls) return "more than 64 controls in one tick";
  out.controls[out.control_count++] = Control::make(static_cast<std::uint16_t>(kind), payload);
  return {};
}

void RecordReader::skip_to_end() {
  TickRecord t;
  while (next(t)) {
  }
}

}  // namespace cathbox::session
