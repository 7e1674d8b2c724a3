#pragma once
// Test fixture: cathbox-emu's box in-process on a real socket, and a virtual clock shared by the
// host side (BoxClient, transports, flasher) and the emulator. Waiting on the clock advances
// the emulator, so everything is deterministic and nothing sleeps.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "device/box_client.hpp"
#include "device/box_opener.hpp"
#include "device/clock.hpp"
#include "emu/emulator.hpp"

namespace cathbox::testing {

class EmuWorld final : public device::Clock {
 public:
  explicit EmuWorld(emu::EmuOptions options = {}) : EmuWorld(std::vector<emu::EmuOptions>{std::move(options)}) {}
  // Several boxes on one rig (one emulator and socket each), all on the same clock.
  explicit EmuWorld(std::vector<emu::EmuOptions> boxes) {
    static std::atomic<int> counter{0};
    for (emu::EmuOptions& o : boxes) {
      Box b;
      b.options = std::move(o);
      b.path = "/tmp/cathbox-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".sock";
      boxes_.push_back(std::move(b));
    }
    for (std::size_t i = 0; i < boxes_.size(); ++i) start(i);
  }

  // (Re)starts the emulator process: a fresh box listening on the same path.
  void start(std::size_t box = 0) {
    Box& b = boxes_.at(box);
    b.emu = std::make_unique<emu::Emulator>(b.options);
    auto listening = b.emu->listen(b.path);
    if (!listening) throw std::runtime_error(listening.error().message);
  }
  // Kills the emulator process: its socket disappears with it.
  void kill(std::size_t box = 0) { boxes_.at(box).emu.reset(); }

  [[nodiscard]] emu::Emulator& emu(std::size_t box = 0) { return *boxes_.at(box).emu; }
  [[nodiscard]] bool running(std::size_t box = 0) const { return boxes_.at(box).emu != nullptr; }
  [[nodiscard]] const std::string& path(std::size_t box = 0) const { return boxes_.at(box).path; }

  // Advances the world (and the emulators that run) by us (a multiple of 10 us).
  void advance(uint64_t us) {
    now_ += us;
    for (Box& b : boxes_) {
      if (b.emu) b.emu->advance(us);
    }
  }

  [[nodiscard]] std::int64_t now_us() override { return static_cast<std::int64_t>(now_); }
  void wait(int /*fd*/, std::int64_t max_us) override {
    const uint64_t step = emu::Emulator::kPhysicsStep_us;
    uint64_t us = static_cast<uint64_t>(std::clamp<std::int64_t>(max_us, 0, 100));
    us = std::max<uint64_t>(step, (us + step - 1) / step * step);
    advance(us);
  }

  [[nodiscard]] device::BoxClient::Opener opener(std::size_t box = 0) { return device::box_opener(path(box), *this); }
  [[nodiscard]] std::unique_ptr<device::BoxClient> connect(std::size_t box = 0) {
    auto client = device::BoxClient::connect(opener(box), *this);
    if (!client) throw std::runtime_error(client.error().message);
    return std::move(client.value());
  }

 private:
  struct Box {
    emu::EmuOptions options;
    std::string path;
    std::unique_ptr<emu::Emulator> emu;
  };
  std::vector<Box> boxes_;
  uint64_t now_ = 0;
};

// A brake command: a wall at wall_um on the insertion axis (stiffness in mN/m), resisting only.
inline cbx_command_report wall_command(int32_t wall_um, int32_t stiffness_mN_per_m) {
  cbx_command_report c{};
  c.mode = CBX_MODE_BRAKE;
  c.insertion = {0, wall_um, stiffness_mN_per_m, 0, -5000, 0};
  c.rotation = {0, 0, 0, 0, 0, 0};
  return c;
}

}  // namespace cathbox::testing
