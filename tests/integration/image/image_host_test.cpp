// The shipped image under the host's own driver: BoxClient over the emulator socket, the same
// path `cathbox info / monitor / calibrate` and the trainer take, in virtual time.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "emu/emulator.hpp"
#include "image_world.hpp"
#include "protocol/cbx_hid_descriptor.h"
#include "protocol/cbx_image_info.h"

namespace cathbox::testing {
namespace {

cbx_image_info image_info(const std::vector<uint8_t>& image) {
  cbx_image_info info{};
  EXPECT_GE(image.size(), CBX_IMAGE_INFO_OFFSET + CBX_IMAGE_INFO_SIZE);
  EXPECT_EQ(cbx_image_info_decode(image.data() + CBX_IMAGE_INFO_OFFSET, CBX_IMAGE_INFO_SIZE, &info), CBX_OK);
  return info;
}

class ImageHost : public ::testing::Test {
 protected:
  void SetUp() override {
    world_.advance(200'000);  // boot and enumeration
    ASSERT_TRUE(world_.emu().enumerated()) << world_.emu().enumeration_error() << world_.emu().error();
    client_ = world_.connect();
  }
  // Advances 1 ms at a time for `ms`, polling the client; the newest state in state_.
  void run_ms(int ms) {
    for (int i = 0; i < ms; ++i) {
      world_.advance(1000);
      (void)client_->poll(state_);
    }
  }

  std::vector<uint8_t> image_ = read_firmware_image();
  ImageWorld world_{image_};
  std::unique_ptr<device::BoxClient> client_;
  device::BoxState state_;
};

TEST_F(ImageHost, ReportsTheImagesOwnInfoAndItsHidDescriptor) {
  const cbx_image_info info = image_info(image_);
  const cbx_device_info& device = client_->device_info();
  EXPECT_STREQ(device.board, info.board);
  EXPECT_STREQ(device.build, info.build);
  EXPECT_EQ(device.fw_major, info.fw_major);
  EXPECT_EQ(device.fw_minor, info.fw_minor);
  EXPECT_EQ(device.fw_patch, info.fw_patch);
  EXPECT_EQ(device.protocol_minor, info.protocol_minor);
  EXPECT_EQ(device.insertion_actuator, CBX_ACTUATOR_BRAKE);
  EXPECT_EQ(device.insertion_encoder_cpr, 2400u);  // the port's board.h (a 600-line encoder)
  EXPECT_EQ(std::strncmp(device.serial, "CBX-", 4), 0) << device.serial;  // from the chip's unique ID
  // The report descriptor the emulated host read back at enumeration is protocol/'s.
  const auto& descriptor = world_.emu().report_descriptor();
  ASSERT_EQ(descriptor.size(), cbx_hid_report_descriptor_size);
  EXPECT_EQ(std::memcmp(descriptor.data(), cbx_hid_report_descriptor, descriptor.size()), 0);
}

TEST_F(ImageHost, StreamsStateReportsAtOneKilohertz) {
  run_ms(10);
  const uint64_t before = client_->stats().states_accepted + client_->stats().states_superseded;
  run_ms(500);
  const auto& stats = client_->stats();
  EXPECT_NEAR(static_cast<double>(stats.states_accepted + stats.states_superseded - before), 500.0, 2.0);
  EXPECT_EQ(stats.states_missed, 0u);
  EXPECT_EQ(stats.rejected(), 0u);
  // A factory-fresh board: an empty settings store, so not calibrated, and nothing else.
  EXPECT_EQ(state_.report.faults, CBX_FAULT_NOT_CALIBRATED);
  EXPECT_EQ(state_.report.board_faults, 0u);  // the 25 MHz crystal started
  EXPECT_EQ(state_.report.in_dropped, 0u);
}

TEST_F(ImageHost, EncoderMotionComesBackInTheReports) {
  // The hand pushes the tool in at 20 mm/s for 300 ms, then pulls the rotation collet round.
  world_.emu().set_hand(0, emu::HandScript::parse("v:20mm/s:300ms,free:1s").value());
  world_.emu().set_hand(1, emu::HandScript::parse("v:-3rad/s:200ms,free:1s").value());
  run_ms(600);
  const int64_t insertion = world_.emu().model().state(0).count;
  const int64_t rotation = world_.emu().model().state(1).count;
  // 6 mm at 108 650 counts/m; the rotation axis backwards (TIM3, 16 bits, extended by the core).
  EXPECT_GT(insertion, 500);
  EXPECT_LT(rotation, -300);
  EXPECT_NEAR(state_.report.insertion_count, insertion, 2);
  EXPECT_NEAR(state_.report.rotation_count, rotation, 2);
}

TEST_F(ImageHost, BrakeWallCommandDrivesTheModelledBrake) {
  ASSERT_TRUE(client_->set_calibration(emu::model_calibration(world_.emu().model())));
  run_ms(20);  // the image saves the calibration to its flash store (about 1 ms)
  EXPECT_EQ(state_.report.faults, 0u);
  // The hand pushes in at 10 mm/s; a 2000 N/m brake wall at 2 mm resists.
  world_.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:1s").value());
  cbx_command_report wall{};
  wall.mode = CBX_MODE_BRAKE;
  wall.insertion = {0, 2'000, 2'000'000, 0, -5000, 0};
  int max_drive = 0;
  // The tick cost counts from here: the ticks before were not rendering.
  world_.emu().machine().reset_tick_instructions_max();
  for (int ms = 0; ms < 600; ++ms) {
    ASSERT_TRUE(client_->send(wall));
    run_ms(1);
    max_drive = std::max<int>(max_drive, std::abs(world_.emu().machine().outputs().drive_permille[0]));
  }
  ASSERT_EQ(world_.emu().error(), "");
  // Past the wall the image's PWM (TIM4 CH1 duty, PB14 enable) brakes the tool.
  const double pos_mm = world_.emu().model().state(0).pos * 1e3;
  EXPECT_GT(pos_mm, 2.0);
  EXPECT_GT(max_drive, 0);
  const int drive = std::abs(world_.emu().machine().outputs().drive_permille[0]);
  // The rendered force (state report) and the PWM agree through the calibration (5 N full
  // scale, linear curve): drive = |force| / 5 N, within a tick's slew and 1 per mille rounding.
  const int expected = static_cast<int>(std::lround(std::abs(state_.report.insertion_force_mN) / 5.0));
  EXPECT_GT(drive, 50);
  EXPECT_NEAR(drive, expected, 10);
  // The tick cost on the whole image (SysTick entry to return, the port's HAL and ADC cycle
  // included) while it renders: within the 2000-instruction budget of firmware/README.md.
  const uint64_t tick_max = world_.emu().machine().tick_instructions_max();
  RecordProperty("tick_instructions_max", static_cast<int>(tick_max));
  EXPECT_GT(tick_max, 500u);
  EXPECT_LE(tick_max, 2000u);

  // The E-stop loop opens just after a tick: the EXTI interrupt cuts the PWM before the next.
  const uint64_t ticks = world_.emu().machine().ticks();
  while (world_.emu().machine().ticks() == ticks) world_.advance(10);
  world_.emu().set_estop(true);
  world_.advance(30);
  EXPECT_EQ(world_.emu().machine().ticks(), ticks + 1);
  EXPECT_EQ(world_.emu().machine().outputs().drive_permille[0], 0);
  run_ms(2);
  EXPECT_NE(state_.report.faults & CBX_FAULT_ESTOP, 0u);
}

// Rendering a brake wall, then a bus event: the outputs go off at once, whatever the host sent.
class ImageHostRendering : public ImageHost {
 protected:
  void SetUp() override {
    ImageHost::SetUp();
    ASSERT_TRUE(client_->set_calibration(emu::model_calibration(world_.emu().model())));
    run_ms(20);
    world_.emu().set_hand(0, emu::HandScript::parse("v:10mm/s:2s").value());
    wall_.mode = CBX_MODE_BRAKE;
    wall_.insertion = {0, 1'000, 2'000'000, 0, -5000, 0};
    render_ms(300);
    ASSERT_NE(world_.emu().machine().outputs().drive_permille[0], 0);
  }
  void render_ms(int ms) {
    for (int i = 0; i < ms; ++i) {
      ASSERT_TRUE(client_->send(wall_));
      run_ms(1);
    }
  }
  cbx_command_report wall_{};
};

TEST_F(ImageHostRendering, BusResetZeroesTheOutputsAndTheBoxEnumeratesAgain) {
  world_.emu().usb_reset();  // 10 ms of reset, then the host's enumeration
  EXPECT_EQ(world_.emu().machine().outputs().drive_permille[0], 0);
  EXPECT_TRUE(world_.emu().enumerated()) << world_.emu().enumeration_error();
  render_ms(100);  // the host's commands are taken again
  EXPECT_NE(world_.emu().machine().outputs().drive_permille[0], 0);
}

TEST_F(ImageHostRendering, SuspendZeroesTheOutputsAndResumeBringsReportsBack) {
  world_.emu().usb_suspend();
  const uint64_t sent = world_.emu().in_reports_sent();
  run_ms(10);
  EXPECT_EQ(world_.emu().machine().outputs().drive_permille[0], 0);
  EXPECT_EQ(world_.emu().in_reports_sent(), sent);  // no tokens on a suspended bus
  world_.emu().usb_resume();
  render_ms(100);
  EXPECT_GT(world_.emu().in_reports_sent(), sent + 90);
  EXPECT_NE(world_.emu().machine().outputs().drive_permille[0], 0);
}

TEST_F(ImageHost, CalibrationSurvivesAPowerCycleInTheFlashStore) {
  const cbx_calibration cal = emu::model_calibration(world_.emu().model());
  ASSERT_TRUE(client_->set_calibration(cal));
  run_ms(20);  // program the block into sector 5's next slot (header last)
  ASSERT_EQ(state_.report.faults, 0u);
  // Power off and on: a new chip with this one's flash (SRAM and peripherals from reset).
  ImageWorld again(world_.emu().machine().flash());
  again.advance(200'000);
  auto client = again.connect();
  device::BoxState state;
  for (int ms = 0; ms < 20; ++ms) {
    again.advance(1000);
    (void)client->poll(state);
  }
  EXPECT_EQ(state.report.faults, 0u);  // calibrated from the store at boot
  auto stored = client->calibration();
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored.value().insertion_counts_per_m, cal.insertion_counts_per_m);
  EXPECT_EQ(stored.value().rotation_full_scale_uNm, cal.rotation_full_scale_uNm);
}

TEST_F(ImageHostRendering, CommandWatchdogCutsTheOutputAt50ms) {
  // The host stops sending: 50 ms later the watchdog fault, then a ramp to 0 within 20 ms.
  run_ms(45);
  EXPECT_EQ(state_.report.faults & CBX_FAULT_WATCHDOG, 0u);
  EXPECT_NE(world_.emu().machine().outputs().drive_permille[0], 0);
  run_ms(30);
  EXPECT_NE(state_.report.faults & CBX_FAULT_WATCHDOG, 0u);
  EXPECT_EQ(world_.emu().machine().outputs().drive_permille[0], 0);
}

TEST_F(ImageHost, IndependentWatchdogResetsAHungTickAndTheBoxComesBack) {
  run_ms(10);
  ASSERT_EQ(world_.emu().machine().watchdog_resets(), 0u);
  // The control tick stops (SysTick off, as if the image hung with it masked): nothing reloads
  // the IWDG, which the image set to 50 ms (LSI 32 kHz / 4, reload 400).
  world_.emu().machine().scs_write(0xE000E010u, 4, 0u);
  run_ms(45);
  EXPECT_EQ(world_.emu().machine().watchdog_resets(), 0u);
  run_ms(10);
  EXPECT_EQ(world_.emu().machine().watchdog_resets(), 1u);
  // The image boots again, re-enumerates, and the client's link comes back.
  run_ms(400);
  EXPECT_TRUE(world_.emu().enumerated());
  EXPECT_EQ(client_->link(), device::Link::kUp);
  EXPECT_GE(client_->stats().reconnects, 1u);
  const uint64_t before = client_->stats().states_accepted;
  run_ms(50);
  EXPECT_GT(client_->stats().states_accepted, before);
}

TEST_F(ImageHost, LimitsRoundTripAndAnOutOfRangeOneIsRefused) {
  auto limits = client_->limits();
  ASSERT_TRUE(limits);
  EXPECT_EQ(limits.value().watchdog_timeout_ms, 50u);  // the firmware's defaults
  cbx_limits tighter = limits.value();
  tighter.max_force_mN = 1200;
  tighter.watchdog_timeout_ms = 80;
  ASSERT_TRUE(client_->set_limits(tighter));
  // Read back at once: the image answers while it saves the limits to its flash store.
  auto read_back = client_->limits();
  ASSERT_TRUE(read_back);
  EXPECT_EQ(read_back.value().max_force_mN, 1200u);
  EXPECT_EQ(read_back.value().watchdog_timeout_ms, 80u);
  // Out of range (protocol: watchdog 5..1000 ms): refused, the limits unchanged.
  cbx_limits bad = tighter;
  bad.watchdog_timeout_ms = 2;
  EXPECT_FALSE(client_->set_limits(bad));
  run_ms(5);
  EXPECT_EQ(client_->limits().value().watchdog_timeout_ms, 80u);
}

TEST_F(ImageHost, SelfTestFailsUncalibratedThenPassesCalibrated) {
  auto wait_selftest = [&] {
    cbx_selftest result{};
    for (int ms = 0; ms < 2000; ms += 10) {
      run_ms(10);
      auto got = client_->selftest();
      if (got && got.value().state != CBX_SELFTEST_RUNNING) return got.value();
    }
    ADD_FAILURE() << "self-test still running after 2 s";
    return result;
  };
  ASSERT_EQ(client_->selftest().value().state, CBX_SELFTEST_NEVER_RUN);
  ASSERT_TRUE(client_->start_selftest());
  cbx_selftest first = wait_selftest();
  EXPECT_EQ(first.state, CBX_SELFTEST_FAILED);
  EXPECT_EQ(first.failed_checks, CBX_CHECK_CALIBRATION);  // the factory image has no calibration
  // The test drive's currents and the supply come through the ADC from the model.
  EXPECT_GT(first.insertion_current_mA, 50);
  EXPECT_GT(first.rotation_current_mA, 50);
  EXPECT_NEAR(first.supply_mV, 24000, 500);
  ASSERT_TRUE(client_->set_calibration(emu::model_calibration(world_.emu().model())));
  run_ms(20);
  ASSERT_TRUE(client_->start_selftest());
  const cbx_selftest second = wait_selftest();
  EXPECT_EQ(second.state, CBX_SELFTEST_PASSED) << "failed checks 0x" << std::hex << second.failed_checks;
  EXPECT_EQ(second.failed_checks, 0u);
}

TEST_F(ImageHost, CounterResetZeroesTheChosenAxisOnly) {
  world_.emu().set_hand(0, emu::HandScript::parse("v:20mm/s:200ms,free:2s").value());
  world_.emu().set_hand(1, emu::HandScript::parse("v:3rad/s:200ms,free:2s").value());
  run_ms(400);
  ASSERT_GT(state_.report.insertion_count, 300);
  const int32_t rotation = state_.report.rotation_count;
  ASSERT_GT(rotation, 300);
  ASSERT_TRUE(client_->reset_counters(CBX_RESET_INSERTION_COUNT));
  run_ms(20);
  EXPECT_NEAR(state_.report.insertion_count, 0, 4);
  EXPECT_NEAR(state_.report.rotation_count, rotation, 4);
  ASSERT_TRUE(client_->reset_counters(CBX_RESET_ROTATION_COUNT | CBX_RESET_ERROR_COUNTERS));
  run_ms(20);
  EXPECT_NEAR(state_.report.rotation_count, 0, 4);
  EXPECT_EQ(state_.report.rx_errors, 0u);
  EXPECT_FALSE(client_->reset_counters(0));  // no bit set: refused (protocol: at least one)
}

}  // namespace
}  // namespace cathbox::testing
