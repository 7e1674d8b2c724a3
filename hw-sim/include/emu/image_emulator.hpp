#pragma once
// `cathbox-emu --image`: the shipped STM32F411 firmware image, run whole on the emulated chip
// (Stm32Machine), inside the physical model of the box (BoxModel), served on the emulator
// socket. The socket's host side is a USB host: it resets the bus when the device connects,
// enumerates it as the kernel would (device, address, configuration, SET_IDLE, report
// descriptor), then turns each socket control request into the SETUP / DATA / STATUS stages on
// endpoint 0, polls interrupt IN endpoint 1 once per frame and sends the socket's OUT reports to
// endpoint 1. A jump into the system memory enters the emulated ROM DfuSe bootloader (as
// Emulator does); leaving it resets into the flashed image.
//
// Schedule: every 10 us the physics and 960 CPU cycles (96 MHz); every 1 ms a USB frame (SOF,
// IN poll, OUT delivery, socket).
#include <array>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "emu/box_model.hpp"
#include "emu/dfu_bootloader.hpp"
#include "emu/emu_server.hpp"
#include "emu/flash_memory.hpp"
#include "emu/result.hpp"
#include "emu/stm32_machine.hpp"

namespace cathbox::emu {

class ImageEmulator final : public EmuServer::Handler {
 public:
  static constexpr uint64_t kPhysicsStep_us = 10;
  static constexpr uint64_t kFrame_us = 1000;

  // `image`: the bytes of a .bin (flash offset 0). Fails without a bootable vector table.
  [[nodiscard]] static Result<std::unique_ptr<ImageEmulator>> create(std::span<const uint8_t> image, bool motor = false);
  ~ImageEmulator() override;

  [[nodiscard]] Result<bool> listen(const std::string& path);
  void advance(uint64_t us);
  void service();
  [[nodiscard]] uint64_t now_us() const { return now_us_; }
  [[nodiscard]] EmuServer* server() { return server_.get(); }
  [[nodiscard]] Stm32Machine& machine() { return machine_; }
  [[nodiscard]] BoxModel& model() { return model_; }
  void set_hand(int axis, HandScript script) { model_.set_script(axis, std::move(script), now_us_); }
  void set_estop(bool pressed) { machine_.inputs().estop_open = pressed; }
  // USB bus events from the host side. usb_reset: a port reset, then enumeration again (as a
  // host recovering a device does); it runs the emulator through both.
  void usb_reset();
  void usb_suspend();
  void usb_resume();
  // Stopped on an emulation error (an unmodelled register, a fault): the message, else empty.
  [[nodiscard]] const std::string& error() const { return machine_.error(); }
  [[nodiscard]] bool enumerated() const { return enumerated_; }
  [[nodiscard]] bool in_bootloader() const { return bootloader_mode_; }
  [[nodiscard]] const std::vector<uint8_t>& report_descriptor() const { return report_descriptor_; }
  [[nodiscard]] const std::string& enumeration_error() const { return enumeration_error_; }
  [[nodiscard]] uint64_t in_reports_sent() const { return in_reports_; }

  // A control transfer on endpoint 0 (as the socket's requests go): false = stalled or timed out.
  bool control(const cbx_usb_setup& setup, std::span<const uint8_t> data, std::vector<uint8_t>& reply);

  // EmuServer::Handler
  [[nodiscard]] bool attached(uint16_t& vid, uint16_t& pid) override;
  void on_out(std::span<const uint8_t> report) override;
  [[nodiscard]] bool on_control(const cbx_usb_setup& setup, std::span<const uint8_t> data,
                                std::vector<uint8_t>& reply) override;

 private:
  explicit ImageEmulator(bool motor);
  void step();
  void frame();
  void enumerate();
  void bus_reset();
  void detach();
  void enter_bootloader();
  void leave_bootloader();

  Stm32Machine machine_;
  BoxModel model_;
  FlashMemory dfu_flash_;
  DfuBootloader bootloader_;
  std::unique_ptr<EmuServer> server_;
  uint64_t now_us_ = 0;
  bool enumerated_ = false;
  bool bootloader_mode_ = false;
  uint64_t retry_at_us_ = 0;
  std::optional<uint64_t> connected_since_us_;  // the D+ pull-up on since, as the host saw it
  uint64_t disconnects_seen_ = 0;               // OtgFs::disconnects() the host has acted on
  uint16_t vid_ = 0, pid_ = 0;
  std::vector<uint8_t> report_descriptor_;
  std::string enumeration_error_;
  std::deque<std::array<uint8_t, 64>> out_queue_;
  uint64_t in_reports_ = 0;
};

}  // namespace cathbox::emu
