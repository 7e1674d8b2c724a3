// The default box's fault injector on the shipped image (ImageEmulator::faults, unplug,
// set_wire_version; the same options of cathbox-emu), under the host's own driver, in virtual
// time: what the host and the image's safety logic make of each fault.
#include <gtest/gtest.h>

#include <cstdlib>

#include "emu/emulator.hpp"
#include "image_world.hpp"

namespace cathbox::testing {
namespace {

class ImageFaults : public ::testing::Test {
 protected:
  void SetUp() override {
    world_.advance(200'000);
    ASSERT_TRUE(world_.emu().enumerated()) << world_.emu().enumeration_error() << world_.emu().error();
    client_ = world_.connect();
  }
  void run_ms(int ms, const cbx_command_report* command = nullptr) {
    for (int i = 0; i < ms; ++i) {
      if (command != nullptr) (void)client_->send(*command);
      world_.advance(1000);
      (void)client_->poll(state_);
    }
  }
  void calibrate() {
    ASSERT_TRUE(client_->set_calibration(emu::model_calibration(world_.emu().model())));
    run_ms(20);
  }
  static cbx_command_report wall() {
    cbx_command_report c{};
    c.mode = CBX_MODE_BRAKE;
    c.insertion = {0, 1'000, 2'000'000, 0, -5000, 0};
    return c;
  }

  ImageWorld world_;
  std::unique_ptr<device::BoxClient> client_;
  device::BoxState state_;
};

TEST_F(ImageFaults, InReportsDroppedAndCorruptedAreCountedByTheHost) {
  run_ms(10);
  emu::LinkFaults& in = world_.emu().faults().in;
  in.drop = 0.1;
  in.corrupt = 0.1;
  run_ms(300);
  const auto& counts = world_.emu().faults().counts();
  const auto& stats = client_->stats();
  EXPECT_GT(counts.dropped, 10u);
  EXPECT_GT(counts.corrupted, 10u);
  // A flipped bit fails the CRC (or the range check); a lost report is a sequence gap. Every
  // corrupted report is refused, and every report the host never accepted is counted missed.
  EXPECT_EQ(stats.rejected(), counts.corrupted);
  EXPECT_GE(stats.states_missed, counts.dropped);
  EXPECT_EQ(world_.emu().machine().watchdog_resets(), 0u);
}

TEST_F(ImageFaults, ACorruptedCommandLatchesBadCommandInTheImage) {
  world_.emu().faults().out.corrupt = 1.0;
  const cbx_command_report off{};
  run_ms(10, &off);
  run_ms(5);
  // One bit flipped fails the CRC: every corrupted command counted, none applied.
  EXPECT_GE(world_.emu().faults().counts().corrupted, 5u);
  EXPECT_EQ(state_.report.rx_errors, world_.emu().faults().counts().corrupted);
  EXPECT_NE(state_.report.faults & CBX_FAULT_BAD_COMMAND, 0u);
}

TEST_F(ImageFaults, DelayedAndDuplicatedCommandsStillRender) {
  calibrate();
  world_.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:2s").value());
  emu::LinkFaults& out = world_.emu().faults().out;
  out.duplicate = 0.5;
  out.delay = 0.3;
  out.delay_us = 3000;  // within the 50 ms command watchdog: reordered, never stale for long
  const cbx_command_report c = wall();
  run_ms(400, &c);
  EXPECT_GT(world_.emu().faults().counts().duplicated, 50u);
  EXPECT_GT(world_.emu().faults().counts().delayed, 50u);
  EXPECT_EQ(state_.report.faults, 0u);
  EXPECT_NE(world_.emu().machine().outputs().drive_permille[0], 0);  // past the 1 mm wall
}

TEST_F(ImageFaults, EncoderBounceReachesTheTimerWithoutAnErrorAndWithoutDrift) {
  world_.emu().faults().encoder.bounce = 0.5;
  world_.emu().set_hand(0, emu::HandScript::parse("v:20mm/s:300ms,free:1s").value());
  run_ms(400);
  EXPECT_GT(world_.emu().faults().counts().bounces, 100u);
  // TIM2 follows the lines: a bounce moves it one count and back, no illegal transition.
  EXPECT_NEAR(state_.report.insertion_count, world_.emu().model().state(0).count, 1);
  EXPECT_EQ(state_.report.encoder_errors, 0u);
  EXPECT_EQ(state_.report.faults & CBX_FAULT_ENCODER, 0u);
}

TEST_F(ImageFaults, MissedEncoderSamplesLoseTheirCounts) {
  // Fast enough for two transitions inside one 10 us sample: 2 m/s on the insertion rollers.
  world_.emu().faults().encoder.skip = 0.2;
  world_.emu().set_hand(0, emu::HandScript::parse("v:2000mm/s:40ms,free:1s").value());
  run_ms(300);
  const uint64_t skips = world_.emu().faults().counts().skips;
  ASSERT_GT(skips, 10u);
  const int64_t lost = world_.emu().encoder_counts_lost(0);
  EXPECT_EQ(lost, 2 * static_cast<int64_t>(skips));
  EXPECT_NEAR(state_.report.insertion_count, world_.emu().model().state(0).count - lost, 1);
}

TEST_F(ImageFaults, UnplugStopsTheOutputsAndTheHostReconnectsAfterReplug) {
  calibrate();
  world_.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:3s").value());
  const cbx_command_report c = wall();
  run_ms(300, &c);
  ASSERT_NE(world_.emu().machine().outputs().drive_permille[0], 0);
  world_.emu().unplug(300'000);
  run_ms(5, &c);
  // The bus went idle: the image's OTG core saw a suspend and turned the outputs off.
  EXPECT_EQ(world_.emu().machine().outputs().drive_permille[0], 0);
  EXPECT_FALSE(world_.emu().enumerated());
  run_ms(250, &c);
  EXPECT_EQ(client_->link(), device::Link::kDown);
  EXPECT_FALSE(world_.emu().enumerated());  // still unplugged
  run_ms(400, &c);                          // replugged at 300 ms, then the 100 ms attach debounce
  EXPECT_TRUE(world_.emu().enumerated());
  EXPECT_EQ(client_->link(), device::Link::kUp);
  EXPECT_EQ(client_->stats().reconnects, 1u);
  EXPECT_NE(world_.emu().machine().outputs().drive_permille[0], 0);  // rendering again
}

TEST_F(ImageFaults, AnotherWireVersionIsRefusedByTheHost) {
  world_.emu().set_wire_version(2);
  auto other = device::BoxClient::connect(world_.opener(), world_);
  ASSERT_FALSE(other);
  EXPECT_NE(other.error().message.find("protocol v2"), std::string::npos) << other.error().message;
}

}  // namespace
}  // namespace cathbox::testing
