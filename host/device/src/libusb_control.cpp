#include "device/libusb_control.hpp"

#include <libusb.h>

#include <chrono>
#include <thread>

#include "protocol/cbx_protocol.h"

namespace cathbox::device {
namespace {

constexpr unsigned kTimeout_ms = 5000;

Error usb_error(const std::string& what, int code) {
  const Errc errc = code == LIBUSB_ERROR_NO_DEVICE ? Errc::kDisconnected
                    : code == LIBUSB_ERROR_PIPE    ? Errc::kStall
                    : code == LIBUSB_ERROR_TIMEOUT ? Errc::kTimeout
                                                   : Errc::kIo;
  return make_error(errc, what + ": " + libusb_error_name(code));
}

}  // namespace

Result<std::vector<std::string>> LibusbControl::list() {
  libusb_context* context = nullptr;
  if (const int rc = libusb_init(&context); rc != 0) return usb_error("libusb_init", rc);
  libusb_device** devices = nullptr;
  const ssize_t n = libusb_get_device_list(context, &devices);
  std::vector<std::string> out;
  for (ssize_t i = 0; i < n; ++i) {
    libusb_device_descriptor d{};
    if (libusb_get_device_descriptor(devices[i], &d) != 0) continue;
    if (d.idVendor == CBX_DFU_VID && d.idProduct == CBX_DFU_PID) {
      out.push_back(std::to_string(libusb_get_bus_number(devices[i])) + "-" +
                    std::to_string(libusb_get_port_number(devices[i])));
    }
  }
  if (n >= 0) libusb_free_device_list(devices, 1);
  libusb_exit(context);
  return out;
}

Result<std::unique_ptr<LibusbControl>> LibusbControl::open(unsigned wait_ms) {
  libusb_context* context = nullptr;
  if (const int rc = libusb_init(&context); rc != 0) return usb_error("libusb_init", rc);
  libusb_device_handle* handle = nullptr;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(wait_ms);
  for (;;) {
    handle = libusb_open_device_with_vid_pid(context, CBX_DFU_VID, CBX_DFU_PID);
    if (handle != nullptr || std::chrono::steady_clock::now() >= deadline) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  if (handle == nullptr) {
    libusb_exit(context);
    return make_error(Errc::kNoDevice,
                      "no STM32 ROM bootloader (USB 0483:df11) found; try --recover-gpio, or check the udev rule");
  }
  if (const int rc = libusb_claim_interface(handle, 0); rc != 0) {
    libusb_close(handle);
    libusb_exit(context);
    return usb_error("claim DFU interface 0", rc);
  }
  if (const int rc = libusb_set_interface_alt_setting(handle, 0, 0); rc != 0) {
    libusb_release_interface(handle, 0);
    libusb_close(handle);
    libusb_exit(context);
    return usb_error("select alternate setting 0", rc);
  }
  return std::unique_ptr<LibusbControl>(new LibusbControl(context, handle));
}

LibusbControl::LibusbControl(libusb_context* context, libusb_device_handle* handle) : context_(context), handle_(handle) {}

LibusbControl::~LibusbControl() {
  libusb_release_interface(handle_, 0);
  libusb_close(handle_);
  libusb_exit(context_);
}

Status LibusbControl::control_out(const UsbSetup& setup, std::span<const uint8_t> data) {
  const int rc = libusb_control_transfer(handle_, setup.request_type, setup.request, setup.value, setup.index,
                                         const_cast<unsigned char*>(data.data()), static_cast<uint16_t>(data.size()),
                                         kTimeout_ms);
  if (rc < 0) return usb_error("control request " + std::to_string(setup.request), rc);
  return Ok{};
}

Result<size_t> LibusbControl::control_in(const UsbSetup& setup, std::span<uint8_t> in) {
  const int rc = libusb_control_transfer(handle_, setup.request_type, setup.request, setup.value, setup.index,
                                         in.data(), static_cast<uint16_t>(in.size()), kTimeout_ms);
  if (rc < 0) return usb_error("control request " + std::to_string(setup.request), rc);
  return static_cast<size_t>(rc);
}

Result<std::string> LibusbControl::alt_name(uint8_t alt) {
  libusb_config_descriptor* config = nullptr;
  if (const int rc = libusb_get_active_config_descriptor(libusb_get_device(handle_), &config); rc != 0) {
    return usb_error("read configuration descriptor", rc);
  }
  uint8_t index = 0;
  if (config->bNumInterfaces > 0 && alt < config->interface[0].num_altsetting) {
    index = config->interface[0].altsetting[alt].iInterface;
  }
  libusb_free_config_descriptor(config);
  if (index == 0) return make_error(Errc::kDeviceError, "bootloader has no alternate setting " + std::to_string(alt));
  unsigned char text[256];
  const int n = libusb_get_string_descriptor_ascii(handle_, index, text, sizeof text);
  if (n < 0) return usb_error("read string descriptor", n);
  return std::string(reinterpret_cast<const char*>(text), static_cast<size_t>(n));
}

void LibusbControl::delay(uint64_t max_us) { std::this_thread::sleep_for(std::chrono::microseconds(max_us)); }

std::string LibusbControl::describe() const { return "usb 0483:df11 (STM32 ROM DFU bootloader)"; }

}  // namespace cathbox::device
