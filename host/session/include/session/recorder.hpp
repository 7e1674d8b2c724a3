#pragma once
// Writes a session record (docs/session/record-format.md). The haptic thread encodes
// each tick into the current block (delta-encoded integers, no allocation); every 1000 ticks, or
// once a second of the session's clock has passed, the block is handed to a writer thread,
// which compresses it (zstd), frames it with its length and CRC-32 and appends it to the file
// with one write. A process killed at any moment leaves every block written so far readable.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include "base/jthread.hpp"
#include "base/result.hpp"
#include <vector>

#include "session/control.hpp"
#include "session/hand.hpp"
#include "session/record_format.hpp"
#include "session/record_header.hpp"
#include "session/spsc_ring.hpp"

namespace cathbox::session {

class Recorder {
 public:
  // Creates (or truncates) `path` and writes the file header and the header block; else the
  // error line when the file cannot be written.
  [[nodiscard]] static base::Result<std::unique_ptr<Recorder>> create(const std::string& path,
                                                                      const RecordHeader& header);
  ~Recorder();
  Recorder(const Recorder&) = delete;
  Recorder& operator=(const Recorder&) = delete;

  // Called on the writer thread after each block reaches the file: ticks recorded so far and
  // the file's size. Set before the first tick.
  void on_block_written(std::function<void(std::int64_t ticks, std::uint64_t bytes)> callback) {
    on_block_ = std::move(callback);
  }

  // The haptic thread, once per tick, in this order: begin_tick, the tick's controls, tools,
  // box (only recorded when it changed), then after the step state_hash and events, end_tick.
  void begin_tick(std::int64_t tick, std::int64_t clock_us);
  void control(const Control& control);
  void tools(const TickInput& input);
  void box(const BoxStatus& status);
  void state_hash(std::uint64_t hash);
  void event(record::EventCode code);
  void end_tick();

  // Ends the record once: seals the last block and queues the end block (the writer thread
  // drains in the background). Later calls do nothing.
  // `haptic_dropped`: a real-time run's dropped haptic ticks (none in virtual time).
  void finish(record::EndReason reason, std::string_view text, std::int64_t ticks, std::int64_t end_unix_us,
              std::optional<std::int64_t> haptic_dropped = std::nullopt);
  // Waits until everything queued is in the file and closes it; false when a write failed.
  bool close();

  // Any thread.
  [[nodiscard]] std::string error() const;
  [[nodiscard]] std::uint64_t bytes_written() const { return bytes_written_.load(std::memory_order_relaxed); }
  [[nodiscard]] std::int64_t ticks_written() const { return ticks_written_.load(std::memory_order_relaxed); }
  [[nodiscard]] const std::string& path() const { return path_; }

 private:
  struct Block {
    record::BlockType type = record::BlockType::kTicks;
    std::int64_t end_tick = 0;  // ticks recorded once this block is written
    std::vector<std::uint8_t> data;
  };
  static constexpr std::size_t kRing = 64;
  static constexpr std::size_t kBlockReserve = 96 * 1024;
  static constexpr std::size_t kBlockSealBytes = 64 * 1024;

  Recorder(int fd, std::string path);
  void writer_loop(base::stop_token stop);
  bool write_block(record::BlockType type, const std::vector<std::uint8_t>& raw, std::vector<std::uint8_t>& out,
                   void* cctx);
  void seal(bool force = false);
  void fail(std::string what);
  void entry_begin(std::uint16_t kind);
  void entry_end();

  int fd_;
  std::string path_;
  std::function<void(std::int64_t, std::uint64_t)> on_block_;
  // Haptic side.
  Block* current_ = nullptr;
  std::size_t entry_start_ = 0;
  std::int64_t block_first_tick_ = 0;
  std::int64_t block_ticks_ = 0;
  std::int64_t block_start_clock_us_ = 0;
  std::int64_t tick_ = 0;
  std::int64_t clock_us_ = 0;
  std::int64_t ticks_recorded_ = 0;
  std::array<ToolCommand, kMaxTools> last_tools_{};
  BoxStatus last_box_{};
  bool finished_ = false;
  std::size_t allocated_ = 0;
  // Hand-over.
  std::vector<std::unique_ptr<Block>> pool_;
  SpscRing<Block*, kRing> full_;
  SpscRing<Block*, kRing> empty_;
  std::atomic<std::uint32_t> pending_{0};
  std::atomic<bool> done_{false};
  // Writer side.
  base::jthread writer_;
  std::atomic<std::uint64_t> bytes_written_{0};
  std::atomic<std::int64_t> ticks_written_{0};
  mutable std::mutex error_mutex_;
  std::string error_;
  bool closed_ = false;
};

}  // namespace cathbox::session
