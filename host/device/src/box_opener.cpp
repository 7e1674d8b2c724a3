#include "device/box_opener.hpp"

#include "device/hidapi_transport.hpp"
#include "device/socket_transport.hpp"
#include "protocol/cbx_protocol.h"

namespace cathbox::device {

BoxClient::Opener box_opener(std::optional<std::string> emu_path, Clock& clock) {
  if (!emu_path) {
    return []() -> Result<std::unique_ptr<Transport>> {
      auto opened = HidapiTransport::open("");
      if (!opened) return opened.error();
      return std::unique_ptr<Transport>(std::move(opened.value()));
    };
  }
  return [path = *emu_path, &clock]() -> Result<std::unique_ptr<Transport>> {
    auto opened = SocketTransport::open(path, clock);
    if (!opened) return opened.error();
    if (opened.value()->pid() != CBX_USB_PID) {
      return make_error(Errc::kNoDevice, "the emulated box at " + path + " is in its DFU bootloader (" +
                                             opened.value()->describe() + "); run 'cathbox flash'");
    }
    return std::unique_ptr<Transport>(std::move(opened.value()));
  };
}

Result<std::string> path_of_serial(std::span<const HidDeviceInfo> boxes, const std::string& serial) {
  std::string found;
  for (const HidDeviceInfo& b : boxes) {
    if (b.serial == serial) return b.path;
    found += (found.empty() ? "" : ", ") + (b.serial.empty() ? std::string("(no serial) ") + b.path : b.serial);
  }
  return make_error(Errc::kNoDevice, "no box with serial '" + serial + "' (" +
                                         (found.empty() ? std::string("no box found") : "found: " + found) + ")");
}

BoxClient::Opener box_opener_by_serial(std::string serial) {
  return [serial = std::move(serial)]() -> Result<std::unique_ptr<Transport>> {
    auto boxes = HidapiTransport::enumerate();
    if (!boxes) return boxes.error();
    auto path = path_of_serial(boxes.value(), serial);
    if (!path) return path.error();
    auto opened = HidapiTransport::open(path.value());
    if (!opened) return opened.error();
    return std::unique_ptr<Transport>(std::move(opened.value()));
  };
}

}  // namespace cathbox::device
