// Safety and link recovery against the emulated box in virtual time: the command watchdog when
// the host stops mid-push, BoxClient recovering from an emulator restart and from an unplug.
#include <gtest/gtest.h>

#include <cstdio>

#include "emu_world.hpp"

namespace cathbox::testing {
namespace {

// Drives the loop for `ms` milliseconds: poll and (if `send`) one command per millisecond.
void run(EmuWorld& world, device::BoxClient& client, const cbx_command_report& command, int ms, bool send,
         device::BoxState& state) {
  for (int i = 0; i < ms; ++i) {
    world.advance(1000);
    (void)client.poll(state);
    if (send) (void)client.send(command);
  }
}

TEST(Watchdog, HostStopsMidPushOutputRampsToZeroAndFaultIsSeenAfterReconnect) {
  EmuWorld world;
  world.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:4s,f:1000mN:10s").value());
  auto client = world.connect();
  const auto command = wall_command(15'000, 2'000'000);
  device::BoxState state;
  run(world, *client, command, 3000, true, state);  // pushing into the wall at 15 mm
  const auto before = world.emu().core_state();
  ASSERT_LT(before.insertion_force_mN, -1000) << "the wall must be pushing back before the host stops";
  ASSERT_NE(world.emu().board().drive_permille[0], 0);

  // The host stops (crashed or hung): no more commands, and it closes its connection.
  const uint64_t last_command_us = world.now_us();
  client.reset();
  const uint64_t timeout_us = 50'000;  // default limits
  uint64_t zero_at = 0;
  for (int i = 0; i < 2000 && zero_at == 0; ++i) {
    world.advance(100);
    if (world.emu().board().drive_permille[0] == 0 && world.emu().core_state().insertion_force_mN == 0) {
      zero_at = world.now_us();
    }
  }
  ASSERT_NE(zero_at, 0u) << "output never reached zero";
  std::printf("watchdog: output zero %.1f ms after the last command (timeout 50 ms)\n", (zero_at - last_command_us) / 1e3);
  EXPECT_LE(zero_at - last_command_us, timeout_us + 20'000);
  EXPECT_GE(zero_at - last_command_us, timeout_us) << "output must not drop before the timeout";
  // Stays at zero while the hand keeps leaning on the tool.
  world.advance(500'000);
  EXPECT_EQ(world.emu().board().drive_permille[0], 0);

  // The host comes back: the latched fault is the first thing it sees.
  auto again = world.connect();
  device::BoxState seen;
  for (int i = 0; i < 5 && !again->poll(seen); ++i) world.advance(1000);
  EXPECT_TRUE(seen.report.faults & CBX_FAULT_WATCHDOG);
  EXPECT_FALSE(seen.report.status & CBX_STATUS_OUTPUT_ENABLED);
  // Acknowledging it while commands flow clears it and the wall is rendered again.
  cbx_command_report ack = command;
  ack.flags = CBX_CMD_ACK_FAULTS;
  run(world, *again, ack, 20, true, seen);
  run(world, *again, command, 200, true, seen);
  EXPECT_EQ(seen.report.faults & CBX_FAULT_WATCHDOG, 0);
  EXPECT_LT(seen.report.insertion_force_mN, -500);
}

TEST(EStop, CutsOutputAtOnceLatchesAndClearsOnlyWhenReleasedAndAcknowledged) {
  EmuWorld world;
  world.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:3s,f:1000mN:10s").value());
  auto client = world.connect();
  const auto command = wall_command(15'000, 2'000'000);
  device::BoxState state;
  run(world, *client, command, 2500, true, state);
  ASSERT_NE(world.emu().board().drive_permille[0], 0);
  world.emu().set_estop(true);
  world.advance(100);  // one control tick
  EXPECT_EQ(world.emu().board().drive_permille[0], 0) << "E-stop must cut the drive at the next tick";
  run(world, *client, command, 5, true, state);
  EXPECT_TRUE(state.report.faults & CBX_FAULT_ESTOP);
  EXPECT_TRUE(state.report.status & CBX_STATUS_ESTOP_PRESSED);
  // Acknowledging while it is still pressed does not clear it.
  cbx_command_report ack = command;
  ack.flags = CBX_CMD_ACK_FAULTS;
  run(world, *client, ack, 20, true, state);
  EXPECT_TRUE(state.report.faults & CBX_FAULT_ESTOP);
  EXPECT_EQ(world.emu().board().drive_permille[0], 0);
  // Released and acknowledged: the wall comes back.
  world.emu().set_estop(false);
  run(world, *client, ack, 20, true, state);
  run(world, *client, command, 200, true, state);
  EXPECT_EQ(state.report.faults & CBX_FAULT_ESTOP, 0);
  EXPECT_NE(world.emu().board().drive_permille[0], 0);
}

TEST(Reconnect, EmulatorKilledAndRestartedRecoversWithinOneSecond) {
  EmuWorld world;
  auto client = world.connect();
  cbx_limits limits{};
  limits.max_force_mN = 3000;
  limits.max_torque_uNm = 40000;
  limits.watchdog_timeout_ms = 80;
  limits.insertion_max_current_mA = 1500;
  limits.rotation_max_current_mA = 1000;
  limits.force_slew_mN_per_ms = 100;
  limits.torque_slew_uNm_per_ms = 1000;
  ASSERT_TRUE(client->set_limits(limits).ok());
  const auto command = wall_command(30'000, 1'000'000);
  device::BoxState state;
  run(world, *client, command, 500, true, state);
  const uint16_t seq_before = client->next_command_seq();

  world.kill();
  run(world, *client, command, 300, true, state);  // the haptic loop keeps calling
  EXPECT_EQ(client->link(), device::Link::kDown);
  world.start();
  const uint64_t restarted_us = world.now_us();
  uint64_t fresh_state_us = 0;
  for (int i = 0; i < 2000 && fresh_state_us == 0; ++i) {
    world.advance(1000);
    if (client->poll(state)) fresh_state_us = world.now_us();
    (void)client->send(command);
  }
  ASSERT_NE(fresh_state_us, 0u) << "BoxClient never recovered";
  std::printf("reconnect after emulator restart: %.1f ms (virtual)\n", (fresh_state_us - restarted_us) / 1e3);
  EXPECT_LE(fresh_state_us - restarted_us, 1'000'000u);
  EXPECT_EQ(client->stats().reconnects, 1u);
  EXPECT_EQ(client->stats().disconnects, 1u);
  // The session survived: the same client, its sequence numbers continue, and the limits it
  // had set are back in the restarted box.
  EXPECT_GT(client->next_command_seq(), seq_before);
  auto restored = client->limits();
  ASSERT_TRUE(restored.ok()) << restored.error().message;
  EXPECT_EQ(restored.value().max_force_mN, 3000u);
  EXPECT_EQ(restored.value().watchdog_timeout_ms, 80u);
  // And the commands flow into the new box: a command sent in one frame is delivered in the
  // next and applied by the following control tick, so the newest state echoes the command
  // sent three polls ago.
  run(world, *client, command, 50, true, state);
  EXPECT_EQ(state.report.command_seq_echo, static_cast<uint16_t>(client->next_command_seq() - 3));
}

TEST(Reconnect, UnplugAndReplugRecoversWithinOneSecond) {
  EmuWorld world;
  auto client = world.connect();
  const auto command = wall_command(30'000, 1'000'000);
  device::BoxState state;
  run(world, *client, command, 100, true, state);
  world.emu().unplug(400'000);
  const uint64_t unplugged_at = world.now_us();
  uint64_t back_at = 0;
  bool went_down = false;
  for (int i = 0; i < 2000 && back_at == 0; ++i) {
    world.advance(1000);
    const bool fresh = client->poll(state);
    went_down = went_down || client->link() == device::Link::kDown;
    if (went_down && fresh) back_at = world.now_us();
    (void)client->send(command);
  }
  ASSERT_TRUE(went_down);
  ASSERT_NE(back_at, 0u);
  EXPECT_LE(back_at - unplugged_at, 400'000u + 1'000'000u);
  EXPECT_GE(back_at - unplugged_at, 400'000u);
  EXPECT_EQ(client->stats().reconnects, 1u);
}

}  // namespace
}  // namespace cathbox::testing
