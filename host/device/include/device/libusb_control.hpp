#pragma once
// Control transfers to a real STM32 ROM DFU bootloader (USB 0483:DF11) through libusb.
#include <memory>
#include <string>
#include <vector>

#include "device/control_transfer.hpp"

struct libusb_context;
struct libusb_device_handle;

namespace cathbox::device {

class LibusbControl final : public ControlTransfer {
 public:
  // "bus-port" locations of attached DFU bootloaders.
  [[nodiscard]] static Result<std::vector<std::string>> list();
  // Opens the first bootloader found (or waits up to wait_ms for one to enumerate).
  [[nodiscard]] static Result<std::unique_ptr<LibusbControl>> open(unsigned wait_ms);
  ~LibusbControl() override;
  LibusbControl(const LibusbControl&) = delete;
  LibusbControl& operator=(const LibusbControl&) = delete;

  [[nodiscard]] Status control_out(const UsbSetup& setup, std::span<const uint8_t> data) override;
  [[nodiscard]] Result<size_t> control_in(const UsbSetup& setup, std::span<uint8_t> in) override;
  [[nodiscard]] Result<std::string> alt_name(uint8_t alt) override;
  void delay(uint64_t max_us) override;
  [[nodiscard]] std::string describe() const override;

 private:
  LibusbControl(libusb_context* context, libusb_device_handle* handle);
  libusb_context* context_;
  libusb_device_handle* handle_;
};

}  // namespace cathbox::device
