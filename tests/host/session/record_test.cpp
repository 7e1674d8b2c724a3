// The record format: what the recorder writes the reader gives back, tick by tick; every
// damage is one line naming the byte; a record cut anywhere reads up to its last complete
// block; a kind the reader does not know is refused, not misread.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>

#include "protocol/cbx_bytes.h"
#include "session/record_format.hpp"
#include "session/record_reader.hpp"
#include "session/recorder.hpp"
#include "scenario/case_file.hpp"

namespace cathbox::session {
namespace {

std::string temp_path(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::path(CATHBOX_BINARY_DIR) / "record_test";
  std::filesystem::create_directories(dir);
  return (dir / name).string();
}

std::vector<std::uint8_t> read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

RecordHeader sample_header() {
  RecordHeader h;
  h.software_version = "9.8.7";
  h.start_unix_us = 1'700'000'000'123'456;
  h.case_name = "two tools";
  h.case_file = "cases/x.case";
  h.case_text = "cathbox-case 1\nvessel x.hclm\n";
  h.vessel_file = "cases/x.hclm";
  h.vessel_text = std::string(5000, 'h');
  h.tools = {tool::default_catheter(), tool::default_guidewire()};
  h.tools[1].inside = h.tools[0].name;
  h.entry = {{1.5, -2.25, 3.0}, {0.0, 0.6, 0.8}};
  h.held_tool = 1;
  h.hand = HandKind::kBox;
  h.hand_description = "emulated box: emulator 1209:cb01 /tmp/e.sock";
  DeviceRecord d;
  d.description = "emulator";
  d.serial = "EMU-0001";
  d.board = "cathbox-emu";
  d.firmware = "1.0.0";
  d.insertion_counts_per_m = 108'650;
  d.rotation_counts_per_rev = 4096;
  d.insertion_full_scale_mN = 5000;
  d.rotation_full_scale_uNm = 50'000;
  d.insertion_actuator = 1;
  h.device = d;
  return h;
}

// Writes `ticks` ticks: tool 1 moves every tick, tool 0 every 7th, a select at tick 10, the
// box status changes at ticks 0 and 500, a hash every 100 ticks, a target event at 1234.
std::string write_sample(const std::string& name, std::int64_t ticks, bool finish = true) {
  const std::string path = temp_path(name);
  std::string error;
  auto created = Recorder::create(path, sample_header());
  EXPECT_TRUE(created) << (created ? "" : created.error().message);
  auto& rec = *created;
  TickInput in;
  in.tool_count = 2;
  for (std::int64_t t = 0; t < ticks; ++t) {
    rec->begin_tick(t, t * 1000);
    if (t == 10) rec->control(Control::select_tool(0));
    in.tools[1].insertion_um += 20;
    in.tools[1].rotation_urad -= 3141;
    if (t % 7 == 0) in.tools[0].insertion_um += 1;
    rec->tools(in);
    rec->box({true, t < 500, static_cast<std::uint16_t>(t < 500 ? 0 : 0x21)});
    if ((t + 1) % 100 == 0) rec->state_hash(0x1234'5678'9abc'def0ULL + static_cast<std::uint64_t>(t));
    if (t == 1234) rec->event(record::EventCode::kTargetReached);
    rec->end_tick();
  }
  if (finish) rec->finish(record::EndReason::kTargetReached, "target reached", ticks, 42);
  EXPECT_TRUE(rec->close()) << rec->error();
  return path;
}

void expect_sample_ticks(RecordReader& r, std::int64_t ticks) {
  TickRecord t;
  ToolCommand tool0;
  ToolCommand tool1;
  for (std::int64_t n = 0; n < ticks; ++n) {
    ASSERT_TRUE(r.next(t)) << n << ": " << r.error();
    tool1.insertion_um += 20;
    tool1.rotation_urad -= 3141;
    if (n % 7 == 0) tool0.insertion_um += 1;
    ASSERT_EQ(t.tick, n);
    ASSERT_EQ(t.tools[0], tool0) << n;
    ASSERT_EQ(t.tools[1], tool1) << n;
    ASSERT_EQ(t.control_count, n == 10 ? 1U : 0U) << n;
    if (n == 10) {
      EXPECT_EQ(t.controls[0].payload[0], 0);
    }
    ASSERT_EQ(t.box_changed, n == 0 || n == 500) << n;
    ASSERT_EQ(t.box, (BoxStatus{true, n < 500, static_cast<std::uint16_t>(n < 500 ? 0 : 0x21)}));
    ASSERT_EQ(t.state_hash.has_value(), (n + 1) % 100 == 0) << n;
    if (t.state_hash) {
      EXPECT_EQ(*t.state_hash, 0x1234'5678'9abc'def0ULL + static_cast<std::uint64_t>(n));
    }
    ASSERT_EQ(t.event_count, n == 1234 ? 1U : 0U) << n;
  }
}

TEST(Record, WhatIsWrittenReadsBackTickByTick) {
  const std::string path = write_sample("roundtrip.cbxrec", 2500);
  std::string error;
  auto r_opened = RecordReader::open(path);
  ASSERT_TRUE(r_opened) << r_opened.error().message;
  auto r = std::move(*r_opened);
  const RecordHeader& h = r->header();
  const RecordHeader want = sample_header();
  EXPECT_EQ(h.software_version, want.software_version);
  EXPECT_EQ(h.start_unix_us, want.start_unix_us);
  EXPECT_EQ(h.case_text, want.case_text);
  EXPECT_EQ(h.vessel_text, want.vessel_text);
  ASSERT_EQ(h.tools.size(), 2U);
  EXPECT_EQ(h.tools[1].inside, "catheter");
  EXPECT_EQ(h.tools[0].sections.size(), want.tools[0].sections.size());
  EXPECT_EQ(h.tools[1].sections.back().curve_deg, want.tools[1].sections.back().curve_deg);
  EXPECT_EQ(h.entry.point_mm, want.entry.point_mm);
  EXPECT_EQ(h.held_tool, 1U);
  EXPECT_EQ(h.hand, HandKind::kBox);
  ASSERT_TRUE(h.device);
  EXPECT_EQ(h.device->serial, "EMU-0001");
  EXPECT_EQ(h.device->insertion_counts_per_m, 108'650U);
  expect_sample_ticks(*r, 2500);
  TickRecord t;
  EXPECT_FALSE(r->next(t));
  EXPECT_TRUE(r->error().empty()) << r->error();
  ASSERT_TRUE(r->finished());
  EXPECT_EQ(r->end()->reason, record::EndReason::kTargetReached);
  EXPECT_EQ(r->end()->ticks, 2500);
  EXPECT_EQ(r->blocks_read(), 1U + 3U + 1U);  // header, 1000 + 1000 + 500 ticks, end
}

TEST(Record, ABlockEverySecondOfTheClockEvenWithFewTicks) {
  const std::string path = temp_path("clock.cbxrec");
  std::string error;
  auto created = Recorder::create(path, sample_header());
  ASSERT_TRUE(created) << (created ? "" : created.error().message);
  auto& rec = *created;
  TickInput in;
  in.tool_count = 2;
  for (std::int64_t t = 0; t < 10; ++t) {  // a stalled loop: 10 ticks over 4.5 s of clock
    rec->begin_tick(t, t * 500'000);
    rec->tools(in);
    rec->end_tick();
  }
  ASSERT_TRUE(rec->close());
  auto r_opened = RecordReader::open(path);
  ASSERT_TRUE(r_opened) << r_opened.error().message;
  auto r = std::move(*r_opened);
  r->skip_to_end();
  EXPECT_EQ(r->ticks_read(), 10);
  // A block closes once a second of clock has passed since its first tick: ticks 0-2, 3-5,
  // 6-8, then 9 (sealed by close); plus the header and end blocks.
  EXPECT_EQ(r->blocks_read(), 1U + 4U + 1U);
}

TEST(Record, CutAnywhereItReadsToTheLastCompleteBlockOrSaysWhere) {
  const std::string path = write_sample("cut.cbxrec", 3000);
  const std::vector<std::uint8_t> whole = read_bytes(path);
  // Block boundaries, from a clean read.
  std::vector<std::size_t> ends;
  {
    auto opened = RecordReader::from_bytes(whole, "x");
    ASSERT_TRUE(opened);
    auto& r = *opened;
    TickRecord t;
    std::size_t blocks = r->blocks_read();
    ends.push_back(r->bytes_read());
    while (r->next(t)) {
      if (r->blocks_read() != blocks) {
        blocks = r->blocks_read();
        ends.push_back(r->bytes_read());
      }
    }
  }
  for (std::size_t cut = 0; cut < whole.size(); ++cut) {
    std::vector<std::uint8_t> part(whole.begin(), whole.begin() + static_cast<std::ptrdiff_t>(cut));
    auto opened = RecordReader::from_bytes(part, "cut.cbxrec");
    if (!opened) {
      EXPECT_EQ(opened.error().message.rfind("cut.cbxrec: byte ", 0), 0U) << opened.error().message;
      continue;
    }
    auto& r = *opened;
    r->skip_to_end();
    const bool at_boundary = std::find(ends.begin(), ends.end(), cut) != ends.end();
    if (at_boundary) {
      EXPECT_TRUE(r->error().empty()) << cut << ": " << r->error();
    } else {
      EXPECT_EQ(r->error().rfind("cut.cbxrec: byte ", 0), 0U) << cut << ": " << r->error();
      EXPECT_EQ(r->error().find('\n'), std::string::npos);
    }
    EXPECT_FALSE(r->finished());
    EXPECT_EQ(r->ticks_read() % 1000, 0) << cut;  // whole blocks only
  }
}

TEST(Record, EveryFlippedByteIsCaughtWithItsPlace) {
  const std::string path = write_sample("flip.cbxrec", 1200);
  const std::vector<std::uint8_t> whole = read_bytes(path);
  for (std::size_t at = 0; at < whole.size(); at += 3) {
    std::vector<std::uint8_t> bad = whole;
    bad[at] ^= 0x40;
    auto r = RecordReader::from_bytes(bad, "flip.cbxrec");
    std::string error = r ? std::string() : r.error().message;
    if (r) {
      (*r)->skip_to_end();
      error = (*r)->error();
    }
    EXPECT_EQ(error.rfind("flip.cbxrec: byte ", 0), 0U) << "byte " << at << " flipped went unnoticed";
  }
}

TEST(Record, ForeignFilesAndOtherVersionsAreRefusedInOneLine) {
  const auto hello = RecordReader::from_bytes({'h', 'e', 'l', 'l', 'o'}, "a.txt");
  ASSERT_FALSE(hello);
  EXPECT_EQ(hello.error().message, "a.txt: byte 5: not a cathbox record: 5 bytes, shorter than the 16-byte file header");
  std::vector<std::uint8_t> bytes = read_bytes(write_sample("version.cbxrec", 10));
  bytes[8] = 45;  // format version 45 (a record before a tick read a released coil still being solved as the step began), CRC fixed up
  const std::uint32_t crc = record::crc32(std::span<const std::uint8_t>(bytes).first(12));
  cbx_put_u32(bytes.data() + 12, crc);
  const auto v45 = RecordReader::from_bytes(bytes, "v45.cbxrec");
  ASSERT_FALSE(v45);
  EXPECT_EQ(v45.error().message, "v45.cbxrec: byte 8: record format version 45, this build reads version 46");
  const auto missing = RecordReader::open("/no/such/record.cbxrec");
  ASSERT_FALSE(missing);
  EXPECT_NE(missing.error().message.find("/no/such/record.cbxrec: cannot open"), std::string::npos);
}

// The sample's file header and header block, then a ticks block written by hand: tick 0 holds
// one entry of `kind` with `payload`. The bytes and where the ticks block starts.
std::pair<std::vector<std::uint8_t>, std::size_t> with_tick_entry(const std::string& name, std::uint64_t kind,
                                                                  const std::vector<std::uint8_t>& payload) {
  std::vector<std::uint8_t> bytes = read_bytes(write_sample(name, 5, false));
  // Cut the ticks block off, keep the file header and the header block.
  const auto probe = RecordReader::from_bytes(bytes, "k");
  EXPECT_TRUE(probe) << probe.error().message;
  if (!probe) return {};
  bytes.resize((*probe)->bytes_read());
  std::vector<std::uint8_t> raw;
  record::ByteWriter w(raw);
  w.u64(0);
  w.u32(1);
  w.varint(kind);
  w.varint(payload.size());
  w.bytes(payload);
  w.u8(0);  // end of tick
  std::vector<std::uint8_t> head;
  record::ByteWriter hw(head);
  hw.u8('T');
  hw.u8(0);
  hw.u16(0);
  hw.u32(static_cast<std::uint32_t>(raw.size()));
  hw.u32(static_cast<std::uint32_t>(raw.size()));
  hw.u32(record::crc32(head, raw));
  const std::size_t block_at = bytes.size();
  bytes.insert(bytes.end(), head.begin(), head.end());
  bytes.insert(bytes.end(), raw.begin(), raw.end());
  return {bytes, block_at};
}

// A newer writer's entry kind (99; 69, the devices range's first unused number; or 38, the
// fluoroscopy range's first unused number) in tick 0.
class UnknownKind : public ::testing::TestWithParam<int> {};

TEST_P(UnknownKind, IsRefusedNotMisread) {
  const int kind = GetParam();
  // One file per parameter: CTest runs the instances side by side.
  const auto [bytes, block_at] = with_tick_entry("kind" + std::to_string(kind) + ".cbxrec", static_cast<std::uint64_t>(kind), {0xEF, 0xBE});
  auto opened = RecordReader::from_bytes(bytes, "new.cbxrec");
  ASSERT_TRUE(opened) << opened.error().message;
  auto& r = *opened;
  TickRecord t;
  EXPECT_FALSE(r->next(t));
  EXPECT_EQ(r->error(), "new.cbxrec: byte " + std::to_string(block_at) +
                            ": tick 0, offset 12 of the block's data: unknown kind " + std::to_string(kind) +
                            " (a newer record? this build knows 1-4 and controls 16, 32-37, 64-68)");
}

// The tools entry's u16 mask: a bit of a tool the record does not have (the sample has 2; bit 4
// is tool 2's insertion, bit 15 tool 7's rotation, past the 6 a case holds) is refused, and a
// one-byte mask (version 12's) is short.
TEST(Record, AToolsEntryMovingAToolTheRecordLacksIsRefused) {
  struct Case {
    std::vector<std::uint8_t> payload;
    std::string what;
  };
  for (const Case& c : {Case{{0x10, 0x00, 0x02}, "tools entry moves tool 2, the record has 2"},
                        Case{{0x00, 0x80, 0x02}, "tools entry moves tool 7, the record has 2"},
                        Case{{0x01}, "tools entry shorter than its 2-byte mask"}}) {
    const auto [bytes, block_at] = with_tick_entry("mask.cbxrec", 1, c.payload);
    auto opened = RecordReader::from_bytes(bytes, "m.cbxrec");
    ASSERT_TRUE(opened) << opened.error().message;
    TickRecord t;
    EXPECT_FALSE((*opened)->next(t));
    EXPECT_EQ((*opened)->error(), "m.cbxrec: byte " + std::to_string(block_at) + ": tick 0, offset 12 of the block's data: " + c.what);
  }
}

INSTANTIATE_TEST_SUITE_P(Record, UnknownKind, ::testing::Values(99, 38, 69));

TEST(Record, ControlsCarryTheirKindAndPayload) {
  const Control c = Control::make(static_cast<std::uint16_t>(ControlKind::kSelectTool), std::vector<std::uint8_t>{3});
  EXPECT_EQ(c.size, 1);
  EXPECT_EQ(c.payload[0], 3);
  EXPECT_EQ(Control::select_next_tool().payload[0], 0xFF);
  ControlQueue q;
  for (std::size_t i = 0; i < ControlQueue::kCapacity; ++i) ASSERT_TRUE(q.post(Control::select_tool(i % 4)));
  EXPECT_FALSE(q.post(c));  // full
  Control out;
  ASSERT_TRUE(q.pop(out));
  EXPECT_EQ(out.payload[0], 0);
  q.close();
  EXPECT_FALSE(q.post(c));
}

// Thirty minutes at 1 kHz of a trainee's hand on the box: the wire moves most ticks in whole
// encoder counts (108,650 counts/m: ~9.2 um each) with a speed that wanders between pushing and
// pulling, the tip twisted now and then (4,096 counts a turn), a hash every 100 ticks, the box's
// status changing a few times. The record stays under 10 MB and reads back whole.
TEST(Record, ThirtyMinutesOfAHandOnTheBoxStayUnderTenMegabytes) {
  const std::string path = temp_path("thirty_minutes.cbxrec");
  std::string error;
  auto created = Recorder::create(path, sample_header());
  ASSERT_TRUE(created) << (created ? "" : created.error().message);
  auto& rec = *created;
  std::mt19937 rng(20261124);
  std::normal_distribution<double> accel(0.0, 0.4);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  constexpr std::int64_t kTicks = 30 * 60 * 1000;
  constexpr double kUmPerCount = 1e6 / 108'650.0;
  constexpr double kUradPerCount = 2.0 * 3.14159265358979 * 1e6 / 4096.0;
  TickInput in;
  in.tool_count = 2;
  double speed_mm_s = 0.0;
  double insertion_um = 0.0;
  double turn_speed_rad_s = 0.0;
  double rotation_urad = 0.0;
  for (std::int64_t t = 0; t < kTicks; ++t) {
    rec->begin_tick(t, t * 1000);
    speed_mm_s = std::clamp(speed_mm_s * 0.999 + accel(rng), -30.0, 30.0);
    insertion_um = std::max(0.0, insertion_um + speed_mm_s);  // um per ms == mm per s
    if (t % 5000 == 0) turn_speed_rad_s = unit(rng) < 0.5 ? 0.0 : (unit(rng) - 0.5) * 6.0;
    rotation_urad += turn_speed_rad_s * 1e3;
    in.tools[1].insertion_um = std::llround(std::floor(insertion_um / kUmPerCount) * kUmPerCount);
    in.tools[1].rotation_urad = std::llround(std::floor(rotation_urad / kUradPerCount) * kUradPerCount);
    rec->tools(in);
    rec->box({true, true, static_cast<std::uint16_t>((t / 400'000) % 2 == 0 ? 0 : 0x01)});
    if ((t + 1) % 100 == 0) rec->state_hash(rng());
    rec->end_tick();
  }
  rec->finish(record::EndReason::kEndedByUser, "run ended by the trainee", kTicks, 0);
  ASSERT_TRUE(rec->close()) << rec->error();
  const auto bytes = std::filesystem::file_size(path);
  std::printf("thirty minutes at 1 kHz: %ju bytes\n", static_cast<std::uintmax_t>(bytes));
  EXPECT_LT(bytes, 10U * 1000U * 1000U);
  auto r_opened = RecordReader::open(path);
  ASSERT_TRUE(r_opened) << r_opened.error().message;
  auto r = std::move(*r_opened);
  TickRecord tr;
  std::int64_t n = 0;
  while (r->next(tr)) ++n;
  EXPECT_TRUE(r->error().empty()) << r->error();
  EXPECT_EQ(n, kTicks);
}

}  // namespace
}  // namespace cathbox::session
