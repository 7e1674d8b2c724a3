// The shipped image against the default box (firmware/core on the simulated board): the same
// scripted session, run on both in lockstep in virtual time through the host's own driver,
// gives the same reports and behaviour within stated tolerances. The two share firmware/core
// and BoxModel; they differ in the port (the image's timers, ADC, SysTick and USB stack against
// the simulated HAL) and in timing: the image's 10 kHz SysTick and 1 kHz frames run at a
// phase of their own, so a report may be one tick apart from the board's.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

#include "../device/emu_world.hpp"
#include "emu/emulator.hpp"
#include "image_world.hpp"

namespace cathbox::testing {
namespace {

struct Deviation {
  int64_t count = 0;
  int32_t force_mN = 0;
  int drive_permille = 0;
};

class ImageVsBoard : public ::testing::Test {
 protected:
  void SetUp() override {
    image_.advance(200'000);
    ASSERT_TRUE(image_.emu().enumerated()) << image_.emu().enumeration_error();
    image_client_ = image_.connect();
    // The default box is factory calibrated with the model's calibration; the image is given it.
    ASSERT_TRUE(image_client_->set_calibration(emu::model_calibration(image_.emu().model())));
    image_run(20);
    board_client_ = board_.connect();
    align();
  }
  void image_run(int ms) {
    for (int i = 0; i < ms; ++i) {
      image_.advance(1000);
      (void)image_client_->poll(image_state_);
    }
  }
  // Brings the later-started world to the other's time (10 us steps).
  void align() {
    const uint64_t a = image_.emu().now_us();
    const uint64_t b = board_.emu().now_us();
    if (a > b) board_.advance((a - b) / 10 * 10);
    if (b > a) image_.advance((b - a) / 10 * 10);
    ASSERT_LE(std::llabs(static_cast<long long>(image_.emu().now_us()) - static_cast<long long>(board_.emu().now_us())), 10);
  }
  // One millisecond on both: the same command (if any) to both, then the newest states.
  void step(const cbx_command_report* command) {
    if (command != nullptr) {
      (void)image_client_->send(*command);
      (void)board_client_->send(*command);
    }
    image_.advance(1000);
    board_.advance(1000);
    (void)image_client_->poll(image_state_);
    (void)board_client_->poll(board_state_);
    const auto& a = image_state_.report;
    const auto& b = board_state_.report;
    worst_.count = std::max<int64_t>(worst_.count, std::llabs(int64_t{a.insertion_count} - b.insertion_count));
    worst_.force_mN = std::max(worst_.force_mN, std::abs(a.insertion_force_mN - b.insertion_force_mN));
    worst_.drive_permille = std::max(worst_.drive_permille, std::abs(image_.emu().machine().outputs().drive_permille[0] -
                                                                      board_.emu().board().drive_permille[0]));
  }
  void set_hand(int axis, const char* script) {
    image_.emu().set_hand(axis, emu::HandScript::parse(script).value());
    board_.emu().set_hand(axis, emu::HandScript::parse(script).value());
  }

  ImageWorld image_;
  EmuWorld board_;
  std::unique_ptr<device::BoxClient> image_client_, board_client_;
  device::BoxState image_state_, board_state_;
  Deviation worst_;
};

TEST_F(ImageVsBoard, TheSameSessionGivesTheSameReportsWithinATick) {
  // The hand pushes at 10 mm/s and turns at 1 rad/s; a 2000 N/m brake wall at 2 mm.
  set_hand(0, "v:10mm/s:500ms,free:1s");
  set_hand(1, "v:1rad/s:300ms,free:1s");
  const cbx_command_report wall = wall_command(2'000, 2'000'000);
  for (int ms = 0; ms < 500; ++ms) step(&wall);
  ASSERT_EQ(image_.emu().error(), "");
  const auto& a = image_state_.report;
  const auto& b = board_state_.report;
  EXPECT_EQ(a.faults, b.faults);
  EXPECT_EQ(a.status, b.status);
  EXPECT_EQ(a.mode, b.mode);
  EXPECT_GT(b.insertion_count, 220);  // the tool went past the 2 mm wall (217 counts) on both
  EXPECT_GT(std::abs(b.insertion_force_mN), 500);
  EXPECT_NEAR(a.rotation_count, b.rotation_count, 4);
  // Tolerances: the tool moves 10 mm/s = 1.1 counts/ms, so a report a tick (0.1 ms) or a frame
  // apart differs by 2 counts; the wall's force by k * 2 counts = 37 mN; the drive by that force
  // over the 5 N full scale, 8 per mille. Measured: 2 counts, 20 mN, 4 per mille.
  RecordProperty("worst_count_difference", static_cast<int>(worst_.count));
  RecordProperty("worst_force_difference_mN", worst_.force_mN);
  RecordProperty("worst_drive_difference_permille", worst_.drive_permille);
  EXPECT_LE(worst_.count, 2);
  EXPECT_LE(worst_.force_mN, 40);
  EXPECT_LE(worst_.drive_permille, 8);
  // The physics followed the same path: the tool's position on both models.
  EXPECT_NEAR(image_.emu().model().state(0).pos * 1e3, board_.emu().model().state(0).pos * 1e3, 0.05);

  // The host stops sending: both latch the command watchdog, the image up to two frames later
  // (its USB path holds the last command in the endpoint's FIFO until a frame delivers it, and
  // its state report until the next IN poll; the board's core takes both at the frame itself).
  int image_at = -1, board_at = -1;
  for (int ms = 0; ms < 80; ++ms) {
    step(nullptr);
    if (image_at < 0 && (image_state_.report.faults & CBX_FAULT_WATCHDOG) != 0) image_at = ms;
    if (board_at < 0 && (board_state_.report.faults & CBX_FAULT_WATCHDOG) != 0) board_at = ms;
  }
  ASSERT_GE(image_at, 0);
  ASSERT_GE(board_at, 0);
  EXPECT_GE(image_at, board_at);
  EXPECT_LE(image_at, board_at + 2);
  EXPECT_EQ(image_.emu().machine().outputs().drive_permille[0], 0);
  EXPECT_EQ(board_.emu().board().drive_permille[0], 0);

  // The E-stop loop opens on both: the ESTOP fault in the next report of each.
  image_.emu().set_estop(true);
  board_.emu().set_estop(true);
  step(nullptr);
  step(nullptr);
  EXPECT_NE(image_state_.report.faults & CBX_FAULT_ESTOP, 0u);
  EXPECT_NE(board_state_.report.faults & CBX_FAULT_ESTOP, 0u);
  EXPECT_EQ(image_state_.report.faults, board_state_.report.faults);
}

}  // namespace
}  // namespace cathbox::testing
