// GPIO recovery through the BootPins interface, with a fake that records the pin sequence.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "device/boot_pins.hpp"
#include "device/gpiod_boot_pins.hpp"

namespace cathbox::device {
namespace {

class FakePins final : public BootPins {
 public:
  std::vector<std::string> log;
  uint64_t now_us = 0;
  bool fail_reset = false;
  Status set_boot0(bool high) override {
    log.push_back(std::to_string(now_us) + " boot0=" + (high ? "1" : "0"));
    return Ok{};
  }
  Status set_reset(bool asserted) override {
    if (fail_reset) return make_error(Errc::kIo, "set NRST: permission denied");
    log.push_back(std::to_string(now_us) + " nrst=" + (asserted ? "low" : "released"));
    return Ok{};
  }
  void delay(uint64_t us) override { now_us += us; }
};

TEST(BootRecovery, EnterBootloaderStrapsBoot0AcrossAResetPulse) {
  FakePins pins;
  ASSERT_TRUE(BootRecovery::enter_bootloader(pins).ok());
  const std::vector<std::string> expected = {"0 boot0=1", "0 nrst=low", "10000 nrst=released"};
  EXPECT_EQ(pins.log, expected);
  EXPECT_EQ(pins.now_us, BootRecovery::kResetPulse_us + BootRecovery::kBootWait_us);
}

TEST(BootRecovery, RunApplicationReleasesBoot0BeforeTheReset) {
  FakePins pins;
  ASSERT_TRUE(BootRecovery::run_application(pins).ok());
  const std::vector<std::string> expected = {"0 boot0=0", "0 nrst=low", "10000 nrst=released"};
  EXPECT_EQ(pins.log, expected);
}

TEST(BootRecovery, PinErrorsStopTheSequence) {
  FakePins pins;
  pins.fail_reset = true;
  auto done = BootRecovery::enter_bootloader(pins);
  ASSERT_FALSE(done.ok());
  EXPECT_NE(done.error().message.find("NRST"), std::string::npos);
}

TEST(GpioConfig, ParsesChipAndLines) {
  auto c = GpioConfig::parse("gpiochip2:5:6");
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c.value().chip, "gpiochip2");
  EXPECT_EQ(c.value().boot0_line, 5u);
  EXPECT_EQ(c.value().nrst_line, 6u);
  for (const char* bad : {"", "gpiochip0", "gpiochip0:17", ":17:27", "gpiochip0:x:27", "gpiochip0:17:17", "gpiochip0:17:99999"}) {
    auto parsed = GpioConfig::parse(bad);
    EXPECT_FALSE(parsed.ok()) << bad;
  }
}

TEST(GpiodBootPins, MissingChipIsAClearError) {
  GpioConfig config;
  config.chip = "gpiochip-that-does-not-exist";
  auto pins = GpiodBootPins::open(config);
  ASSERT_FALSE(pins.ok());
  EXPECT_NE(pins.error().message.find("gpiochip-that-does-not-exist"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::device
