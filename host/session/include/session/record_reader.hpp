#pragma once
// Reads a session record (docs/session/record-format.md): the header, then the ticks
// one at a time (a block is read, checked and decompressed when its first tick is needed).
// Every problem is one line "FILE: byte N: what" naming the byte in the file (for a problem
// inside a compressed block: the block's first byte, and the offset within its data), and the
// reader stops there; the ticks before it were delivered. A record that simply ends after a
// complete block (the recording process was killed) is not an error: it has no end block.
#include <array>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "base/result.hpp"
#include "session/control.hpp"
#include "session/hand.hpp"
#include "session/record_format.hpp"
#include "session/record_header.hpp"

namespace cathbox::session {

// One recorded tick, with the tools' positions already accumulated from their deltas.
struct TickRecord {
  static constexpr std::size_t kMaxControls = 64;
  static constexpr std::size_t kMaxEvents = 8;
  std::int64_t tick = 0;
  std::array<ToolCommand, kMaxTools> tools{};
  BoxStatus box{};                 // the last box status recorded (this tick or before)
  bool box_changed = false;
  std::optional<std::uint64_t> state_hash;
  std::array<Control, kMaxControls> controls{};
  std::size_t control_count = 0;
  std::array<record::EventCode, kMaxEvents> events{};
  std::size_t event_count = 0;
};

struct RecordEnd {
  record::EndReason reason = record::EndReason::kStopped;
  std::string text;
  std::int64_t ticks = 0;
  std::int64_t end_unix_us = 0;
  // A real-time run's ticks its haptic loop dropped (it fell behind by more than its catch-up);
  // none for a run in virtual time or a record from before the field.
  std::optional<std::int64_t> haptic_dropped_ticks;
};

class RecordReader {
 public:
  // Opens and reads the file header and the header block; else the error line.
  [[nodiscard]] static base::Result<std::unique_ptr<RecordReader>> open(const std::string& path);
  // The same over bytes in memory (fuzzing, uploads); `name` stands for the file in errors.
  [[nodiscard]] static base::Result<std::unique_ptr<RecordReader>> from_bytes(std::vector<std::uint8_t> bytes,
                                                                              const std::string& name);
  ~RecordReader();
  RecordReader(const RecordReader&) = delete;
  RecordReader& operator=(const RecordReader&) = delete;

  [[nodiscard]] const RecordHeader& header() const { return header_; }

  // The next tick: false at the end of the record (see finished()) or at an error (error()).
  [[nodiscard]] bool next(TickRecord& out);
  // Reads through the rest of the ticks (after next() returned false this is immediate).
  void skip_to_end();

  [[nodiscard]] const std::string& error() const { return error_; }
  // The end block, once next() reached it; empty for a record whose writer was killed.
  [[nodiscard]] const std::optional<RecordEnd>& end() const { return end_; }
  [[nodiscard]] bool finished() const { return end_.has_value(); }
  [[nodiscard]] std::int64_t ticks_read() const { return next_tick_; }
  [[nodiscard]] std::uint64_t bytes_read() const { return file_pos_; }
  [[nodiscard]] std::size_t blocks_read() const { return blocks_; }

 private:
  RecordReader(std::string name) : name_(std::move(name)) {}
  bool fail(std::uint64_t byte, const std::string& what);
  bool read_exact(std::uint8_t* out, std::size_t n, std::size_t& got);
  // Reads the next block: false at a clean end of file (eof = true) or an error.
  bool read_block(record::BlockType& type, bool& eof);
  bool start();
  bool parse_end(std::uint64_t at);
  bool decode_tick(TickRecord& out);
  // One entry of a tick into `out` (tool positions and box status into the reader's running
  // state): an empty string, or what is wrong with it.
  std::string decode_entry(std::uint64_t kind, std::span<const std::uint8_t> payload, TickRecord& out);
  std::string decode_tools(record::ByteReader& p);
  std::string decode_control(std::uint64_t kind, std::span<const std::uint8_t> payload, TickRecord& out);
  bool entry_error(const std::string& what);

  std::string name_;
  std::FILE* file_ = nullptr;
  std::vector<std::uint8_t> memory_;
  bool from_memory_ = false;
  std::uint64_t file_pos_ = 0;
  RecordHeader header_;
  std::string error_;
  std::optional<RecordEnd> end_;
  // The current ticks block.
  std::vector<std::uint8_t> stored_;
  std::vector<std::uint8_t> raw_;
  std::uint64_t block_at_ = 0;     // file offset of the current block
  std::size_t pos_ = 0;            // in raw_
  std::int64_t block_left_ = 0;    // ticks left in the current block
  std::int64_t next_tick_ = 0;
  std::size_t blocks_ = 0;
  std::array<ToolCommand, kMaxTools> tools_{};
  BoxStatus box_{};
  bool stopped_ = false;           // error or end reached
  void* dctx_ = nullptr;
};

}  // namespace cathbox::session
