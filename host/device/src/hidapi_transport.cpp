#include "device/hidapi_transport.hpp"

#include <hidapi/hidapi.h>

#include <cstdio>
#include <cwchar>

#include "protocol/cbx_protocol.h"

namespace cathbox::device {
namespace {

std::string narrow(const wchar_t* text) {
  std::string out;
  if (text == nullptr) return out;
  for (; *text != L'\0'; ++text) out.push_back(*text < 0x80 ? static_cast<char>(*text) : '?');
  return out;
}

std::string hid_error_text(hid_device* device) { return narrow(hid_error(device)); }

bool hid_ready() {
  static const bool ready = hid_init() == 0;
  return ready;
}

}  // namespace

Result<std::vector<HidDeviceInfo>> HidapiTransport::enumerate() {
  if (!hid_ready()) return make_error(Errc::kIo, "hidapi: hid_init failed");
  std::vector<HidDeviceInfo> out;
  hid_device_info* list = hid_enumerate(CBX_USB_VID, CBX_USB_PID);
  for (const hid_device_info* d = list; d != nullptr; d = d->next) {
    out.push_back({d->path != nullptr ? d->path : "", narrow(d->serial_number), narrow(d->product_string),
                   d->vendor_id, d->product_id});
  }
  hid_free_enumeration(list);
  return out;
}

Result<std::unique_ptr<HidapiTransport>> HidapiTransport::open(const std::string& path) {
  auto found = enumerate();
  if (!found) return found.error();
  std::string chosen = path;
  if (chosen.empty()) {
    if (found.value().empty()) {
      return make_error(Errc::kNoDevice, "no box (USB 1209:cb01) found; is it plugged in and the udev rule installed?");
    }
    chosen = found.value().front().path;
  }
  hid_device* device = hid_open_path(chosen.c_str());
  if (device == nullptr) {
    return make_error(Errc::kNoDevice, "cannot open " + chosen + " (permissions? see host/device/README.md, udev rule)");
  }
  if (hid_set_nonblocking(device, 1) != 0) {
    hid_close(device);
    return make_error(Errc::kIo, "cannot make " + chosen + " non-blocking");
  }
  hid_device* writer = hid_open_path(chosen.c_str());
  if (writer == nullptr) {
    hid_close(device);
    return make_error(Errc::kNoDevice, "cannot open " + chosen + " a second time for writing");
  }
  return std::unique_ptr<HidapiTransport>(new HidapiTransport(device, writer, chosen));
}

HidapiTransport::HidapiTransport(hid_device* device, hid_device* writer_device, std::string path)
    : device_(device), writer_device_(writer_device), path_(std::move(path)), writer_([this] { writer_loop(); }) {}

HidapiTransport::~HidapiTransport() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_one();
  writer_.join();
  hid_close(writer_device_);
  hid_close(device_);
}

void HidapiTransport::writer_loop() {
  Report report{};
  for (;;) {
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [this] { return stop_ || mailbox_full_; });
      if (stop_) return;
      report = mailbox_;
      mailbox_full_ = false;
    }
    // hid_write may wait for the interrupt OUT transfer; only this thread waits.
    if (hid_write(writer_device_, report.data(), report.size()) < 0) {
      std::lock_guard lock(mutex_);
      failed_ = true;
    }
  }
}

IoStatus HidapiTransport::read_in(Report& report) {
  {
    std::lock_guard lock(mutex_);
    if (failed_) return IoStatus::kDisconnected;
  }
  const int n = hid_read(device_, report.data(), report.size());
  if (n < 0) return IoStatus::kDisconnected;
  if (n == 0) return IoStatus::kEmpty;
  // A short read cannot be a protocol report; it is handed up so the decoder counts it.
  for (size_t i = static_cast<size_t>(n); i < report.size(); ++i) report[i] = 0;
  if (n != static_cast<int>(kReportSize)) report[0] = 0;
  return IoStatus::kOk;
}

IoStatus HidapiTransport::write_out(const Report& report) {
  {
    std::lock_guard lock(mutex_);
    if (failed_) return IoStatus::kDisconnected;
    mailbox_ = report;
    mailbox_full_ = true;
  }
  wake_.notify_one();
  return IoStatus::kOk;
}

Status HidapiTransport::get_feature(uint8_t id, Report& report) {
  report.fill(0);
  report[0] = id;
  const int n = hid_get_feature_report(device_, report.data(), report.size());
  if (n < 0) return make_error(Errc::kIo, path_ + ": GET_REPORT 0x" + std::to_string(id) + ": " + hid_error_text(device_));
  if (n != static_cast<int>(kReportSize)) {
    return make_error(Errc::kBadReport, path_ + ": feature report is " + std::to_string(n) + " bytes, not 64");
  }
  return Ok{};
}

Status HidapiTransport::set_feature(const Report& report) {
  const int n = hid_send_feature_report(device_, report.data(), report.size());
  if (n < 0) return make_error(Errc::kStall, path_ + ": SET_REPORT refused: " + hid_error_text(device_));
  return Ok{};
}

std::string HidapiTransport::describe() const {
  char id[16];
  std::snprintf(id, sizeof id, "%04x:%04x", CBX_USB_VID, CBX_USB_PID);
  return std::string("hidraw ") + id + " " + path_;
}

}  // namespace cathbox::device
