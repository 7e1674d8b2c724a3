#pragma once
// Endpoint-0 control transfers, the path of DfuSe flashing. One implementation drives a real
// bootloader through libusb, another the emulated one through the emulator socket.
#include <cstdint>
#include <span>
#include <string>

#include "device/result.hpp"

namespace cathbox::device {

struct UsbSetup {
  uint8_t request_type = 0;  // bmRequestType: bit 7 = device-to-host
  uint8_t request = 0;       // bRequest
  uint16_t value = 0;        // wValue
  uint16_t index = 0;        // wIndex
};

class ControlTransfer {
 public:
  virtual ~ControlTransfer() = default;
  // Host-to-device request with data stage `data` (wLength = data.size()).
  [[nodiscard]] virtual Status control_out(const UsbSetup& setup, std::span<const uint8_t> data) = 0;
  // Device-to-host request reading up to in.size() bytes; returns the count received.
  [[nodiscard]] virtual Result<size_t> control_in(const UsbSetup& setup, std::span<uint8_t> in) = 0;
  // The name string of alternate setting `alt` of interface 0 (DfuSe: the memory layout,
  // e.g. "@Internal Flash  /0x08000000/04*016Kg,01*064Kg,03*128Kg").
  [[nodiscard]] virtual Result<std::string> alt_name(uint8_t alt) = 0;
  // Waits max_us (DfuSe bwPollTimeout); virtual in tests.
  virtual void delay(uint64_t max_us) = 0;
  [[nodiscard]] virtual std::string describe() const = 0;
};

}  // namespace cathbox::device
