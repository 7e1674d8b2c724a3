// The image's settings store (firmware/ports/stm32f411/flash_store.c, a log of 264-byte slots
// in flash sector 5) under the host's own driver, in virtual time: `cathbox calibrate`'s
// sequence answered while the image saves, the calibration through a power cycle, the sector
// erased at boot (not while a host waits) once more than half of it is used, and a save into a
// full sector.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>

#include "emu/emulator.hpp"
#include "image_world.hpp"
#include "protocol/cbx_protocol.h"

namespace cathbox::testing {
namespace {

constexpr size_t kStore = 0x20000;  // sector 5, from the flash base
constexpr size_t kSlotBytes = 264;  // header (magic, size) + the 256-byte maximum block
constexpr size_t kSlots = 0x20000 / kSlotBytes;
constexpr uint32_t kMagic = 0xCB5E7701u;

uint32_t word_at(const std::vector<uint8_t>& flash, size_t offset) {
  uint32_t w = 0;
  std::memcpy(&w, flash.data() + offset, sizeof w);
  return w;
}
std::vector<uint8_t> slot(const std::vector<uint8_t>& flash, size_t i) {
  const auto begin = flash.begin() + static_cast<std::ptrdiff_t>(kStore + i * kSlotBytes);
  return {begin, begin + static_cast<std::ptrdiff_t>(kSlotBytes)};
}
bool slot_blank(const std::vector<uint8_t>& flash, size_t i) {
  const auto s = slot(flash, i);
  return std::all_of(s.begin(), s.end(), [](uint8_t b) { return b == 0xFF; });
}

// A booted, enumerated image with BoxClient connected; `flash`: the chip's flash at power-on.
class ImageStore : public ::testing::Test {
 protected:
  void boot(std::vector<uint8_t> flash) {
    world_ = std::make_unique<ImageWorld>(std::move(flash));
    world_->advance(200'000);
    ASSERT_TRUE(world_->emu().enumerated()) << world_->emu().enumeration_error() << world_->emu().error();
    client_ = world_->connect();
    run_ms(5);
  }
  void run_ms(int ms) {
    for (int i = 0; i < ms; ++i) {
      world_->advance(1000);
      (void)client_->poll(state_);
    }
  }
  // The end of `cathbox calibrate`: write the calibration, read it back at once.
  void write_and_read_back(const cbx_calibration& cal) {
    const uint64_t t0 = world_->emu().now_us();
    const uint64_t ticks0 = world_->emu().machine().ticks();
    ASSERT_TRUE(client_->set_calibration(cal));
    auto back = client_->calibration();
    ASSERT_TRUE(back) << back.error().message;
    EXPECT_EQ(back.value().insertion_counts_per_m, cal.insertion_counts_per_m);
    EXPECT_EQ(back.value().insertion_full_scale_mN, cal.insertion_full_scale_mN);
    // Both transfers within USB 2.0 9.2.6.4's 500 ms, and the 10 kHz tick ran through them.
    const uint64_t elapsed_us = world_->emu().now_us() - t0;
    EXPECT_LT(elapsed_us, 50'000u);
    EXPECT_GE(world_->emu().machine().ticks() - ticks0, elapsed_us / 100 - 2);
    run_ms(5);  // the main loop's save: about 1 ms of word programs
    ASSERT_EQ(world_->emu().error(), "");
  }
  // Power off and on: a new chip with this one's flash.
  void power_cycle() {
    client_.reset();
    boot(world_->emu().machine().flash());
  }
  cbx_calibration calibration(uint32_t full_scale_mN) {
    cbx_calibration cal = emu::model_calibration(world_->emu().model());
    cal.insertion_full_scale_mN = full_scale_mN;
    return cal;
  }

  std::vector<uint8_t> image_ = read_firmware_image();
  std::unique_ptr<ImageWorld> world_;
  std::unique_ptr<device::BoxClient> client_;
  device::BoxState state_;
};

TEST_F(ImageStore, CalibrateIsAnsweredDuringTheSaveAndSurvivesAPowerCycle) {
  boot(image_);
  ASSERT_EQ(state_.report.faults, CBX_FAULT_NOT_CALIBRATED);  // factory image, sector 5 erased
  // `cathbox calibrate`'s sequence: counters zeroed, the tool moved, the calibration written and
  // read back at once (before, the image masked interrupts through a 1 s erase: exit 5).
  ASSERT_TRUE(client_->reset_counters(CBX_RESET_INSERTION_COUNT | CBX_RESET_ROTATION_COUNT));
  world_->emu().set_hand(0, emu::HandScript::parse("v:20mm/s:200ms,free:1s").value());
  run_ms(250);
  EXPECT_GT(state_.report.insertion_count, 300);
  write_and_read_back(calibration(5000));
  EXPECT_EQ(state_.report.faults, 0u);
  // The block is in slot 0, header last; slot 1 is still blank.
  const auto flash = world_->emu().machine().flash();
  EXPECT_EQ(word_at(flash, kStore), kMagic);
  EXPECT_EQ(word_at(flash, kStore + 4), 2u * CBX_REPORT_SIZE);
  EXPECT_TRUE(slot_blank(flash, 1));
  // A second save goes to the next slot; the newest is the one a power cycle loads.
  write_and_read_back(calibration(4000));
  EXPECT_EQ(word_at(world_->emu().machine().flash(), kStore + kSlotBytes), kMagic);
  power_cycle();
  EXPECT_EQ(state_.report.faults, 0u);  // calibrated from the store at boot
  auto stored = client_->calibration();
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored.value().insertion_full_scale_mN, 4000u);
  EXPECT_EQ(stored.value().insertion_counts_per_m, calibration(4000).insertion_counts_per_m);
}

TEST_F(ImageStore, ASectorMoreThanHalfUsedIsErasedAtBootKeepingTheNewestBlock) {
  boot(image_);
  write_and_read_back(calibration(5000));
  write_and_read_back(calibration(3000));
  // 300 of the 496 slots used: 299 copies of the older block, the newer one last.
  std::vector<uint8_t> flash = world_->emu().machine().flash();
  const auto older = slot(flash, 0);
  const auto newer = slot(flash, 1);
  for (size_t i = 0; i < 299; ++i) std::copy(older.begin(), older.end(), flash.begin() + static_cast<std::ptrdiff_t>(kStore + i * kSlotBytes));
  std::copy(newer.begin(), newer.end(), flash.begin() + static_cast<std::ptrdiff_t>(kStore + 299 * kSlotBytes));
  // An interrupted save after it (data programmed, header blank) is neither loaded nor reused.
  flash[kStore + 300 * kSlotBytes + 8] = 0x00;
  client_.reset();
  world_ = std::make_unique<ImageWorld>(flash);
  world_->advance(300'000);
  EXPECT_FALSE(world_->emu().enumerated());  // erasing (1 s) before USB starts
  world_->advance(1'000'000);
  ASSERT_TRUE(world_->emu().enumerated()) << world_->emu().error();
  EXPECT_EQ(world_->emu().machine().watchdog_resets(), 0u);  // the erase loop reloads the IWDG
  const auto after = world_->emu().machine().flash();
  EXPECT_EQ(slot(after, 0), newer);
  EXPECT_TRUE(slot_blank(after, 1));
  EXPECT_TRUE(slot_blank(after, 300));
  client_ = world_->connect();
  auto stored = client_->calibration();
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored.value().insertion_full_scale_mN, 3000u);
}

TEST_F(ImageStore, ASaveIntoAFullSectorErasesItAndKeepsTheNewBlock) {
  boot(image_);
  write_and_read_back(calibration(5000));
  // Every slot used while the box runs (the last resort: more saves than slots since boot).
  const auto block = slot(world_->emu().machine().flash(), 0);
  for (size_t i = 1; i < kSlots; ++i) world_->emu().machine().write_flash(static_cast<uint32_t>(kStore + i * kSlotBytes), block);
  ASSERT_TRUE(client_->set_calibration(calibration(2000)));
  run_ms(1500);  // the erase blocks USB for its second (documented), then slot 0
  ASSERT_EQ(world_->emu().error(), "");
  const auto flash = world_->emu().machine().flash();
  EXPECT_EQ(word_at(flash, kStore), kMagic);
  EXPECT_TRUE(slot_blank(flash, 1));
  power_cycle();
  auto stored = client_->calibration();
  ASSERT_TRUE(stored);
  EXPECT_EQ(stored.value().insertion_full_scale_mN, 2000u);
}

}  // namespace
}  // namespace cathbox::testing
