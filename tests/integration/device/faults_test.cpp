// Fault injection against the emulated box in virtual time: corrupt and malformed reports are
// rejected and counted on both sides and never acted on; drops, duplicates and delays show up
// as sequence gaps and stale reports, not as wrong states; encoder noise does not move the
// decoded position by more than one count.
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <set>

#include "emu_world.hpp"

namespace cathbox::testing {
namespace {

TEST(Faults, CorruptReportsAreRejectedAndCountedOnBothSides) {
  EmuWorld world;
  auto client = world.connect();
  world.emu().faults().in.corrupt = 0.05;
  world.emu().faults().out.corrupt = 0.05;
  // Every command asks for a different wall position; a corrupted command that were acted on
  // would show up as an echo of a sequence number the box never validly received.
  device::BoxState state;
  std::set<uint16_t> echoes;
  for (int ms = 0; ms < 5000; ++ms) {
    world.advance(1000);
    if (client->poll(state)) echoes.insert(state.report.command_seq_echo);
    ASSERT_TRUE(client->send(wall_command(10'000 + ms, 1'000'000)));
  }
  world.advance(3000);
  (void)client->poll(state);
  const auto& counts = world.emu().faults().counts();
  ASSERT_GT(counts.corrupted, 300u);
  // Host side: every corrupted IN report was rejected (a flipped bit fails the CRC, or the id
  // or version check first).
  const uint64_t host_rejected = client->stats().rejected();
  EXPECT_GT(host_rejected, 100u);
  // Box side: every corrupted OUT report was rejected, counted in rx_errors, and latched.
  const uint64_t box_rejected = state.report.rx_errors;
  EXPECT_GT(box_rejected, 100u);
  EXPECT_EQ(host_rejected + box_rejected, counts.corrupted);
  EXPECT_TRUE(state.report.faults & CBX_FAULT_BAD_COMMAND);
  // None acted on: the box applied exactly the commands that arrived intact.
  EXPECT_EQ(world.emu().out_reports_delivered() - box_rejected, 5000u - box_rejected);
  EXPECT_LE(echoes.size(), 5000u - box_rejected + 1u);
  std::printf("corrupted %llu reports: host rejected %llu, box rejected %llu\n",
              static_cast<unsigned long long>(counts.corrupted), static_cast<unsigned long long>(host_rejected),
              static_cast<unsigned long long>(box_rejected));
}

TEST(Faults, MalformedDatagramsAreCountedAndDropped) {
  EmuWorld world;
  auto client = world.connect();
  // A misbehaving program on the same socket sends garbage datagrams.
  const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, world.path().c_str(), sizeof addr.sun_path - 1);
  ASSERT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  world.advance(1000);
  const uint8_t junk1[3] = {0x03, 0, 0};                    // OUT frame without a report
  uint8_t junk2[68] = {0x02};                               // an IN frame sent to the box
  uint8_t junk3[68] = {0x03};                               // OUT frame with a garbage report
  for (int i = 4; i < 68; ++i) junk3[i] = static_cast<uint8_t>(i * 31);
  ASSERT_GT(::send(fd, junk1, sizeof junk1, 0), 0);
  ASSERT_GT(::send(fd, junk2, sizeof junk2, 0), 0);
  ASSERT_GT(::send(fd, junk3, sizeof junk3, 0), 0);
  device::BoxState state;
  for (int i = 0; i < 5; ++i) {
    world.advance(1000);
    (void)client->poll(state);
  }
  EXPECT_EQ(world.emu().server()->counts().malformed, 2u);  // framing errors
  EXPECT_EQ(state.report.rx_errors, 1u);                     // the garbage report reached the core and was refused
  EXPECT_TRUE(state.report.faults & CBX_FAULT_BAD_COMMAND);
  ::close(fd);
}

TEST(Faults, DropsDuplicatesAndDelaysAreSeenAsGapsAndStaleReports) {
  EmuWorld world;
  auto client = world.connect();
  auto& in = world.emu().faults().in;
  in.drop = 0.02;
  in.duplicate = 0.02;
  in.delay = 0.02;
  in.delay_us = 3000;  // later than the next reports: arrives out of order
  device::BoxState state;
  uint16_t last_seq = 0;
  bool have = false;
  uint64_t backwards = 0;
  for (int ms = 0; ms < 10'000; ++ms) {
    world.advance(1000);
    if (client->poll(state)) {
      if (have && static_cast<uint16_t>(state.report.header.seq - last_seq) >= 0x8000u) ++backwards;
      last_seq = state.report.header.seq;
      have = true;
    }
    (void)client->send(wall_command(30'000, 1'000'000));
  }
  const auto& counts = world.emu().faults().counts();
  const auto& stats = client->stats();
  EXPECT_EQ(backwards, 0u) << "BoxClient must never hand out an older state";
  EXPECT_GT(counts.dropped, 100u);
  EXPECT_GT(stats.states_stale, counts.duplicated / 2);  // duplicates and late reports are ignored
  EXPECT_GT(stats.states_missed, counts.dropped);        // drops and still-delayed reports are gaps
  EXPECT_EQ(stats.rejected(), 0u);
}

TEST(Faults, EncoderNoiseOverAMillionTransitionsKeepsPositionWithinOneCount) {
  EmuWorld world;
  world.emu().faults().encoder.bounce = 0.01;
  world.emu().faults().encoder.skip = 0.002;
  // Back and forth at 2 m/s (about 2 transitions per 10 us sample, so samples do miss edges),
  // then rest.
  std::string script;
  for (int i = 0; i < 5; ++i) script += "v:2000mm/s:450ms,v:-2000mm/s:450ms,";
  script += "free:100ms";
  world.emu().set_hand(0, emu::HandScript::parse(script).value());
  world.emu().set_hand(1, emu::HandScript::parse("v:60rad/s:2s,v:-60rad/s:2s,free:500ms").value());
  world.advance(5'000'000);
  const auto state = world.emu().core_state();
  const auto& counts = world.emu().faults().counts();
  const uint64_t transitions = world.emu().edges_fed();
  std::printf("encoder noise: %llu transitions, %llu bounces, %llu missed samples; error %lld / %lld counts\n",
              static_cast<unsigned long long>(transitions), static_cast<unsigned long long>(counts.bounces),
              static_cast<unsigned long long>(counts.skips),
              static_cast<long long>(state.insertion_count - world.emu().true_count(0)),
              static_cast<long long>(state.rotation_count - world.emu().true_count(1)));
  EXPECT_GE(transitions, 1'000'000u);
  EXPECT_GT(counts.bounces, 5'000u);
  EXPECT_GT(counts.skips, 500u);
  EXPECT_LE(std::llabs(state.insertion_count - world.emu().true_count(0)), 1);
  EXPECT_LE(std::llabs(state.rotation_count - world.emu().true_count(1)), 1);
  EXPECT_GT(state.encoder_errors, 0u);  // the missed samples were seen and counted
}

}  // namespace
}  // namespace cathbox::testing
