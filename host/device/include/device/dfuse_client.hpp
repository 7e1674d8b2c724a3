#pragma once
// A DfuSe client (DFU 1.1 + ST's extensions, as the STM32 ROM bootloader speaks it): status
// polling with bwPollTimeout, set address, sector erase, download, upload, leave. Runs over
// any ControlTransfer (libusb for a real bootloader, the socket for the emulated one).
#include <cstdint>
#include <span>
#include <vector>

#include "device/control_transfer.hpp"
#include "device/result.hpp"

namespace cathbox::device {

struct DfuStatus {
  uint8_t status = 0;  // bStatus (cbx_dfu_status)
  uint32_t poll_timeout_ms = 0;
  uint8_t state = 0;  // bState (cbx_dfu_state)
};

class DfuseClient {
 public:
  explicit DfuseClient(ControlTransfer& usb, uint16_t transfer_size = 2048) : usb_(usb), transfer_size_(transfer_size) {}

  [[nodiscard]] Result<DfuStatus> get_status();
  // Clears an error and aborts any transfer: the bootloader ends in dfuIDLE.
  [[nodiscard]] Status ensure_idle();
  [[nodiscard]] Status set_address(uint32_t address);
  [[nodiscard]] Status erase(uint32_t sector_address);
  // Downloads data at address in transfer-size blocks (the sectors must be erased).
  [[nodiscard]] Status write(uint32_t address, std::span<const uint8_t> data);
  // Uploads length bytes from address.
  [[nodiscard]] Result<std::vector<uint8_t>> read(uint32_t address, size_t length);
  // Jumps to the application at address: zero-length DNLOAD, then manifestation.
  [[nodiscard]] Status leave(uint32_t address);
  [[nodiscard]] uint16_t transfer_size() const { return transfer_size_; }

 private:
  [[nodiscard]] Status dnload(uint16_t block, std::span<const uint8_t> data);
  // Polls GETSTATUS (waiting bwPollTimeout between polls) until the state is `want`.
  [[nodiscard]] Status wait_state(uint8_t want, const char* what);
  [[nodiscard]] Status command(uint8_t code, uint32_t address, const char* what);

  ControlTransfer& usb_;
  uint16_t transfer_size_;
};

}  // namespace cathbox::device
