#include "session/recorder.hpp"

#include <fcntl.h>
#include <unistd.h>
#include <zstd.h>

#include <cerrno>
#include <cstring>

#include "base/byte_order.hpp"

namespace cathbox::session {
namespace {

using record::BlockType;
using record::ByteWriter;
using record::EntryKind;

constexpr int kZstdLevel = 3;

// All n bytes to fd (retrying short writes and EINTR), or the system's reason.
base::Status<> write_all(int fd, const std::uint8_t* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return base::Error{std::strerror(errno)};
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return base::Ok{};
}

struct ZstdContext {
  ZSTD_CCtx* cctx = ZSTD_createCCtx();
  ~ZstdContext() { ZSTD_freeCCtx(cctx); }
};

}  // namespace

Recorder::Recorder(int fd, std::string path) : fd_(fd), path_(std::move(path)) {}

base::Result<std::unique_ptr<Recorder>> Recorder::create(const std::string& path, const RecordHeader& header) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (fd < 0) return base::Error{path + ": cannot write the record: " + std::strerror(errno)};
  std::unique_ptr<Recorder> r(new Recorder(fd, path));
  // The file header: magic, format version, reserved, CRC-32 of the 12 bytes before it.
  std::vector<std::uint8_t> head;
  ByteWriter w(head);
  w.bytes(record::kMagic);
  w.u16(record::kFormatVersion);
  w.u16(0);
  w.u32(record::crc32(head));
  std::vector<std::uint8_t> out;
  ZstdContext z;
  if (const base::Status<> wrote = write_all(fd, head.data(), head.size()); !wrote) {
    return base::Error{path + ": cannot write the record: " + wrote.error().message};
  }
  if (!r->write_block(BlockType::kHeader, encode_header(header), out, z.cctx)) {
    return base::Error{path + ": cannot write the record: " + r->error()};
  }
  r->bytes_written_.store(head.size() + out.size(), std::memory_order_relaxed);
  for (std::size_t i = 0; i < 8; ++i) {
    r->pool_.push_back(std::make_unique<Block>());
    r->pool_.back()->data.reserve(kBlockReserve);
    if (i > 0) (void)r->empty_.push(r->pool_.back().get());
  }
  r->current_ = r->pool_.front().get();
  r->allocated_ = r->pool_.size();
  for (std::size_t t = 0; t < kMaxTools; ++t) r->last_tools_[t] = {};
  r->writer_ = base::jthread([raw = r.get()](base::stop_token stop) { raw->writer_loop(std::move(stop)); });
  return r;
}

Recorder::~Recorder() { (void)close(); }

void Recorder::fail(std::string what) {
  const std::lock_guard lock(error_mutex_);
  if (error_.empty()) error_ = path_ + ": " + std::move(what);
}

std::string Recorder::error() const {
  const std::lock_guard lock(error_mutex_);
  return error_;
}

// Frames `raw` as a block (compressed when that is smaller) into `out` and appends it.
bool Recorder::write_block(BlockType type, const std::vector<std::uint8_t>& raw, std::vector<std::uint8_t>& out,
                           void* cctx) {
  if (raw.size() > record::kMaxBlockBytes) {
    fail("a block of " + std::to_string(raw.size()) + " bytes exceeds the 16 MiB limit");
    return false;
  }
  const std::size_t bound = ZSTD_compressBound(raw.size());
  out.resize(record::kBlockHeaderSize + std::max(bound, raw.size()));
  std::uint8_t* payload = out.data() + record::kBlockHeaderSize;
  std::size_t stored = ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(cctx), payload, bound, raw.data(), raw.size(), kZstdLevel);
  auto compression = record::Compression::kZstd;
  if (ZSTD_isError(stored) || stored >= raw.size()) {
    std::copy(raw.begin(), raw.end(), payload);
    stored = raw.size();
    compression = record::Compression::kNone;
  }
  out.resize(record::kBlockHeaderSize + stored);
  std::vector<std::uint8_t> header;
  header.reserve(record::kBlockHeaderSize);
  ByteWriter w(header);
  w.u8(static_cast<std::uint8_t>(type));
  w.u8(static_cast<std::uint8_t>(compression));
  w.u16(0);
  w.u32(static_cast<std::uint32_t>(stored));
  w.u32(static_cast<std::uint32_t>(raw.size()));
  w.u32(record::crc32(header, std::span<const std::uint8_t>(payload, stored)));
  std::copy(header.begin(), header.end(), out.begin());
  if (const base::Status<> wrote = write_all(fd_, out.data(), out.size()); !wrote) {
    fail("write failed: " + wrote.error().message);
    return false;
  }
  return true;
}

void Recorder::writer_loop(base::stop_token stop) {
  ZstdContext z;
  std::vector<std::uint8_t> out;
  out.reserve(kBlockReserve);
  bool broken = false;
  for (;;) {
    const std::uint32_t seen = pending_.load(std::memory_order_acquire);
    Block* b = nullptr;
    while (full_.pop(b)) {
      if (!broken) {
        broken = !write_block(b->type, b->data, out, z.cctx);
        if (!broken) {
          // The block is in the kernel's page cache (survives the process); ask for the disk.
          (void)::fdatasync(fd_);
          bytes_written_.fetch_add(out.size(), std::memory_order_relaxed);
          ticks_written_.store(b->end_tick, std::memory_order_relaxed);
          if (on_block_) on_block_(b->end_tick, bytes_written_.load(std::memory_order_relaxed));
        }
      }
      b->data.clear();
      (void)empty_.push(b);
    }
    if (done_.load(std::memory_order_acquire) && full_.empty()) return;
    if (stop.stop_requested() && full_.empty()) return;
    pending_.wait(seen, std::memory_order_acquire);
  }
}

void Recorder::begin_tick(std::int64_t tick, std::int64_t clock_us) {
  if (finished_) return;
  tick_ = tick;
  clock_us_ = clock_us;
  if (block_ticks_ == 0) {
    block_first_tick_ = tick;
    block_start_clock_us_ = clock_us;
    ByteWriter w(current_->data);
    w.u64(static_cast<std::uint64_t>(tick));
    w.u32(0);  // tick count, filled in when the block is sealed
  }
}

void Recorder::entry_begin(std::uint16_t kind) {
  ByteWriter w(current_->data);
  w.varint(kind);
  entry_start_ = current_->data.size();
  current_->data.push_back(0);  // length; every entry of this version is shorter than 128 bytes
}

void Recorder::entry_end() {
  const std::size_t length = current_->data.size() - entry_start_ - 1;
  current_->data[entry_start_] = static_cast<std::uint8_t>(length);
}

void Recorder::control(const Control& c) {
  if (finished_) return;
  entry_begin(c.kind);
  ByteWriter(current_->data).bytes(c.bytes());
  entry_end();
}

static_assert(2 * kMaxTools <= 16, "the tools entry's mask is a u16: two bits a tool");

void Recorder::tools(const TickInput& in) {
  if (finished_) return;
  std::uint16_t mask = 0;
  for (std::size_t t = 0; t < in.tool_count && t < kMaxTools; ++t) {
    if (in.tools[t].insertion_um != last_tools_[t].insertion_um) mask |= static_cast<std::uint16_t>(1u << (2 * t));
    if (in.tools[t].rotation_urad != last_tools_[t].rotation_urad) mask |= static_cast<std::uint16_t>(1u << (2 * t + 1));
  }
  if (mask == 0) return;
  entry_begin(static_cast<std::uint16_t>(EntryKind::kTools));
  ByteWriter w(current_->data);
  w.u16(mask);
  for (std::size_t t = 0; t < in.tool_count && t < kMaxTools; ++t) {
    if (mask & (1u << (2 * t))) w.zigzag(in.tools[t].insertion_um - last_tools_[t].insertion_um);
    if (mask & (1u << (2 * t + 1))) w.zigzag(in.tools[t].rotation_urad - last_tools_[t].rotation_urad);
    last_tools_[t] = in.tools[t];
  }
  entry_end();
}

void Recorder::box(const BoxStatus& status) {
  if (finished_ || status == last_box_) return;
  last_box_ = status;
  entry_begin(static_cast<std::uint16_t>(EntryKind::kBoxStatus));
  ByteWriter w(current_->data);
  w.u8(static_cast<std::uint8_t>((status.present ? 1u : 0u) | (status.link_up ? 2u : 0u)));
  w.u16(status.faults);
  entry_end();
}

void Recorder::state_hash(std::uint64_t hash) {
  if (finished_) return;
  entry_begin(static_cast<std::uint16_t>(EntryKind::kStateHash));
  ByteWriter(current_->data).u64(hash);
  entry_end();
}

void Recorder::event(record::EventCode code) {
  if (finished_) return;
  entry_begin(static_cast<std::uint16_t>(EntryKind::kEvent));
  ByteWriter(current_->data).u8(static_cast<std::uint8_t>(code));
  entry_end();
}

void Recorder::end_tick() {
  if (finished_) return;
  current_->data.push_back(static_cast<std::uint8_t>(EntryKind::kEndOfTick));
  ++block_ticks_;
  ticks_recorded_ = tick_ + 1;
  if (block_ticks_ >= static_cast<std::int64_t>(record::kTicksPerBlock) ||
      clock_us_ - block_start_clock_us_ >= record::kBlockSpan_us || current_->data.size() >= kBlockSealBytes) {
    seal();
  }
}

void Recorder::seal(bool force) {
  if (block_ticks_ == 0) return;
  Block* next = nullptr;
  if (!empty_.pop(next)) {
    if (allocated_ + 2 >= kRing && !force) {
      // The writer is a minute behind (a stalled disk): keep filling this block (it grows)
      // rather than lose ticks; the 16 MiB block limit turns a longer stall into an error.
      return;
    }
    pool_.push_back(std::make_unique<Block>());
    next = pool_.back().get();
    ++allocated_;
  }
  // Patch the tick count (bytes 8..11 of the block's data).
  const auto n = static_cast<std::uint32_t>(block_ticks_);
  base::put_le<std::uint32_t>(current_->data.data() + 8, n);
  current_->type = BlockType::kTicks;
  current_->end_tick = block_first_tick_ + block_ticks_;
  (void)full_.push(current_);
  pending_.fetch_add(1, std::memory_order_release);
  pending_.notify_one();
  current_ = next;
  block_ticks_ = 0;
}

void Recorder::finish(record::EndReason reason, std::string_view text, std::int64_t ticks, std::int64_t end_unix_us,
                      std::optional<std::int64_t> haptic_dropped) {
  if (finished_) return;
  seal(true);
  // The end block goes through the same queue, after the last ticks.
  auto end = std::make_unique<Block>();
  end->type = BlockType::kEnd;
  end->end_tick = ticks;
  ByteWriter w(end->data);
  const std::uint8_t code = static_cast<std::uint8_t>(reason);
  w.field(static_cast<std::uint32_t>(record::EndTag::kReason), std::span(&code, 1));
  w.field_text(static_cast<std::uint32_t>(record::EndTag::kReasonText), text);
  w.field_u64(static_cast<std::uint32_t>(record::EndTag::kTicks), static_cast<std::uint64_t>(ticks));
  w.field_u64(static_cast<std::uint32_t>(record::EndTag::kEndUnix_us), static_cast<std::uint64_t>(end_unix_us));
  if (haptic_dropped) {
    w.field_u64(static_cast<std::uint32_t>(record::EndTag::kHapticDropped), static_cast<std::uint64_t>(*haptic_dropped));
  }
  if (full_.push(end.get())) pool_.push_back(std::move(end));
  finished_ = true;
  done_.store(true, std::memory_order_release);
  pending_.fetch_add(1, std::memory_order_release);
  pending_.notify_one();
}

bool Recorder::close() {
  if (closed_) return error().empty();
  closed_ = true;
  if (!finished_) finish(record::EndReason::kStopped, "", ticks_recorded_, 0);
  if (writer_.joinable()) writer_.join();
  if (::close(fd_) != 0) fail(std::string("close failed: ") + std::strerror(errno));
  return error().empty();
}

}  // namespace cathbox::session
