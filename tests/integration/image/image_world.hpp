#pragma once
// Test fixture: the cross-built STM32F411 image on the emulated chip (emu::ImageEmulator), in
// process, on a real socket, with one virtual clock shared by the host side (BoxClient,
// transports, flasher) and the emulator, as emu_world.hpp does for the core's emulator.
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "device/box_client.hpp"
#include "device/box_opener.hpp"
#include "device/clock.hpp"
#include "emu/image_emulator.hpp"

namespace cathbox::testing {

// The image scripts/test's firmware step builds, or $CATHBOX_FIRMWARE_IMAGE.
inline std::string firmware_image_path() {
  if (const char* env = std::getenv("CATHBOX_FIRMWARE_IMAGE"); env != nullptr && *env != '\0') return env;
  return std::string(CATHBOX_SOURCE_DIR) + "/build/stm32f411/bin/stm32f411_firmware.bin";
}

inline std::vector<uint8_t> read_firmware_image() {
  const std::string path = firmware_image_path();
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw std::runtime_error(path + ": no firmware image (build it: scripts/build stm32f411, or set CATHBOX_FIRMWARE_IMAGE)");
  }
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

class ImageWorld final : public device::Clock {
 public:
  explicit ImageWorld(std::vector<uint8_t> image = read_firmware_image(), bool motor = false) {
    static std::atomic<int> counter{0};
    path_ = "/tmp/cathbox-image-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".sock";
    auto created = emu::ImageEmulator::create(image, motor);
    if (!created) throw std::runtime_error(created.error().message);
    emu_ = std::move(created.value());
    auto listening = emu_->listen(path_);
    if (!listening) throw std::runtime_error(listening.error().message);
  }

  [[nodiscard]] emu::ImageEmulator& emu() { return *emu_; }
  [[nodiscard]] const std::string& path() const { return path_; }

  // Advances the world by us (a multiple of 10 us).
  void advance(uint64_t us) { emu_->advance(us); }

  [[nodiscard]] std::int64_t now_us() override { return static_cast<std::int64_t>(emu_->now_us()); }
  void wait(int /*fd*/, std::int64_t max_us) override {
    const uint64_t step = emu::ImageEmulator::kPhysicsStep_us;
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
  std::string path_;
  std::unique_ptr<emu::ImageEmulator> emu_;
};

}  // namespace cathbox::testing
