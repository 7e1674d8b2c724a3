#pragma once
// Test fixture: cathbox-emu's box in-process on a real socket, and a virtual clock shared by the
// host side (BoxClient, transports, flasher) and the emulator. Waiting on the clock advances
// the emulator, so everything is deterministic and nothing sleeps.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <string>

#include "device/box_client.hpp"
#include "device/box_opener.hpp"
#include "device/clock.hpp"
#include "emu/emulator.hpp"

namespace cathbox::testing {

class EmuWorld final : public device::Clock {
 public:
  explicit EmuWorld(emu::EmuOptions options = {}) : options_(std::move(options)) {
    static std::atomic<int> counter{0};
    path_ = "/tmp/cathbox-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".sock";
    start();
  }

  // (Re)starts the emulator process: a fresh box listening on the same path.
  void start() {
    emu_ = std::make_unique<emu::Emulator>(options_);
    auto listening = emu_->listen(path_);
    if (!listening) throw std::runtime_error(listening.error().message);
  }
  // Kills the emulator process: its socket disappears with it.
  void kill() { emu_.reset(); }

  [[nodiscard]] emu::Emulator& emu() { return *emu_; }
  [[nodiscard]] bool running() const { return emu_ != nullptr; }
  [[nodiscard]] const std::string& path() const { return path_; }

  // Advances the world (and the emulator, when running) by us (a multiple of 10 us).
  void advance(uint64_t us) {
    now_ += us;
    if (emu_) emu_->advance(us);
  }

  [[nodiscard]] std::int64_t now_us() override { return static_cast<std::int64_t>(now_); }
  void wait(int /*fd*/, std::int64_t max_us) override {
    const uint64_t step = emu::Emulator::kPhysicsStep_us;
    uint64_t us = static_cast<uint64_t>(std::clamp<std::int64_t>(max_us, 0, 100));
    us = std::max<uint64_t>(step, (us + step - 1) / step * step);
    advance(us);
  }

  [[nodiscard]] device::BoxClient::Opener opener() { return device::box_opener(path_, *this); }
  [[nodiscard]] std::unique_ptr<device::BoxClient> connect() {
    auto client = device::BoxClient::connect(opener(), *this);
    if (!client) throw std::runtime_error(client.error().message);
    return std::move(client.value());
  }

 private:
  emu::EmuOptions options_;
  std::string path_;
  std::unique_ptr<emu::Emulator> emu_;
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
