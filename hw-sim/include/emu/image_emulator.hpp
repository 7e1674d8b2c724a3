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
#include "emu/fault_injector.hpp"
#include "emu/flash_memory.hpp"
#include "emu/result.hpp"
#include "emu/stm32_machine.hpp"

namespace cathbox::emu {

class ImageEmulator final : public EmuServer::Handler {
 public:
  static constexpr uint64_t kPhysicsStep_us = 10;
  static constexpr uint64_t kFrame_us = 1000;

  // `image`: the bytes of a .bin (flash offset 0). Fails without a bootable vector table.
  // `seed`: the fault injector's.
  [[nodiscard]] static Result<std::unique_ptr<ImageEmulator>> create(std::span<const uint8_t> image, bool motor = false,
                                                                     uint64_t seed = 1);
  ~ImageEmulator() override;

  [[nodiscard]] Status listen(const std::string& path);
  void advance(uint64_t us);
  void service();
  [[nodiscard]] uint64_t now_us() const { return now_us_; }
  [[nodiscard]] EmuServer* server() { return server_.get(); }
  [[nodiscard]] Stm32Machine& machine() { return machine_; }
  [[nodiscard]] BoxModel& model() { return model_; }
  void set_hand(int axis, HandScript script) { model_.set_script(axis, std::move(script), now_us_); }
  void set_estop(bool pressed) { machine_.inputs().estop_open = pressed; }
  // The faults of the default box (FaultInjector), on the image: IN packets the host polls and
  // OUT reports it sends are dropped, duplicated, corrupted or delayed on their way between the
  // socket and endpoint 1; encoder noise reaches TIM2/TIM3 (a bounce moves the counter one
  // count for 10 us and back; a missed sample, both lines changing at once, is no count for
  // the timer: the two counts are lost).
  [[nodiscard]] FaultInjector& faults() { return faults_; }
  // As Emulator::set_wire_version: byte 1 of every report the image sends (IN packets, feature
  // GET_REPORT replies) rewritten with a valid CRC.
  void set_wire_version(uint8_t version) { wire_version_ = version; }
  // The cable pulled for duration_us: the socket's connections close, the bus goes idle (the
  // image's OTG core sees a suspend), then the host debounces the attach and enumerates again.
  void unplug(uint64_t duration_us);
  // Counts TIM2/TIM3 lost to missed samples (model count minus counter), per axis.
  [[nodiscard]] int64_t encoder_counts_lost(int axis) const { return -encoder_lost_[static_cast<size_t>(axis)]; }
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
  struct Pending {
    uint64_t due_us;
    std::array<uint8_t, 64> report;
  };
  ImageEmulator(bool motor, uint64_t seed);
  void step();
  int64_t encoder_noise(size_t axis, int64_t steps);
  void send_in(std::span<const uint8_t> packet);
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
  FaultInjector faults_;
  uint8_t wire_version_;
  uint64_t unplugged_until_us_ = 0;
  std::array<int64_t, 2> encoder_lost_{};  // counter minus model count, from missed samples
  std::deque<Pending> in_delayed_, out_delayed_;
};

}  // namespace cathbox::emu
