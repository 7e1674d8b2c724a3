// The foot pedal: debouncing in virtual time through a fake switch, the --pedal-gpio syntax,
// and the GPIO backend's error path (no GPIO on the test machines).
#include <gtest/gtest.h>

#include <vector>

#include "device/foot_pedal.hpp"
#include "device/gpiod_foot_pedal.hpp"

namespace cathbox::device {
namespace {

// A switch whose raw level follows a script of (time_us, level) steps with contact bounce.
class FakeFootPedal final : public FootPedal {
 public:
  explicit FakeFootPedal(std::vector<std::pair<std::uint64_t, bool>> steps) : steps_(std::move(steps)) {}
  void set_time(std::uint64_t now_us) { now_ = now_us; }
  Result<bool> read() override {
    bool level = false;
    for (const auto& [t, v] : steps_) {
      if (t <= now_) level = v;
    }
    return level;
  }

 private:
  std::vector<std::pair<std::uint64_t, bool>> steps_;
  std::uint64_t now_ = 0;
};

TEST(FootPedal, DebouncesContactBounce) {
  // Pressed at 10 ms with 3 ms of bounce, released at 500 ms with 2 ms of bounce, and a 1 ms
  // glitch at 300 ms that must not count.
  FakeFootPedal pedal({{10'000, true}, {10'600, false}, {11'100, true}, {12'000, false}, {13'000, true},
                       {300'000, false}, {301'000, true},
                       {500'000, false}, {500'700, true}, {501'200, false}});
  PedalDebouncer debouncer;
  std::vector<std::pair<std::uint64_t, bool>> changes;
  bool last = false;
  for (std::uint64_t t = 0; t <= 700'000; t += 1'000) {  // read at 1 kHz
    pedal.set_time(t);
    const Result<bool> raw = pedal.read();
    ASSERT_TRUE(raw.ok());
    const bool state = debouncer.update(raw.value(), t);
    if (state != last) changes.emplace_back(t, state);
    last = state;
  }
  ASSERT_EQ(changes.size(), 2u);
  EXPECT_EQ(changes[0], (std::pair<std::uint64_t, bool>{18'000, true}));   // stable from 13 ms, 5 ms hold
  EXPECT_EQ(changes[1], (std::pair<std::uint64_t, bool>{507'000, false}));  // stable from 501.2 ms
}

TEST(FootPedal, ParsesTheGpioOption) {
  const Result<PedalConfig> c = PedalConfig::parse("gpiochip1:23");
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c.value().chip, "gpiochip1");
  EXPECT_EQ(c.value().line, 23u);
  EXPECT_TRUE(c.value().active_low);
  const Result<PedalConfig> high = PedalConfig::parse("/dev/gpiochip0:5:active-high");
  ASSERT_TRUE(high.ok());
  EXPECT_FALSE(high.value().active_low);
  for (const char* bad : {"", "gpiochip0", ":22", "gpiochip0:x", "gpiochip0:2000", "gpiochip0:22:sideways"}) {
    const Result<PedalConfig> r = PedalConfig::parse(bad);
    ASSERT_FALSE(r.ok()) << bad;
    EXPECT_EQ(r.error().code, Errc::kBadArgument);
    EXPECT_EQ(r.error().message.find("--pedal-gpio '" + std::string(bad) + "': "), 0u) << r.error().message;
  }
}

TEST(FootPedal, GpiodBackendNamesTheChipItCannotOpen) {
  PedalConfig config;
  config.chip = "gpiochip-that-does-not-exist";
  const auto pedal = GpiodFootPedal::open(config);
  ASSERT_FALSE(pedal.ok());
  EXPECT_EQ(pedal.error().code, Errc::kIo);
  EXPECT_NE(pedal.error().message.find("gpiochip-that-does-not-exist"), std::string::npos);
  EXPECT_NE(pedal.error().message.find("foot pedal"), std::string::npos);
}

}  // namespace
}  // namespace cathbox::device
