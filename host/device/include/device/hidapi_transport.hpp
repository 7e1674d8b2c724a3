#pragma once
// A real box over hidapi's hidraw backend (hidapi-hidraw), matched by the protocol's VID:PID.
// Reads are non-blocking (hid_set_nonblocking); writes go through a one-slot mailbox to a writer
// thread, because a hidraw write waits for its interrupt OUT transfer (up to a frame) and the
// haptic thread must not. A newer command replaces one the writer has not sent yet. The writer
// has a handle of its own on the same hidraw node: hidapi keeps a per-handle error string that
// every hid_read and hid_write frees and replaces, so one handle shared by two threads races
// (a double free when the box is unplugged and both calls fail).
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "device/transport.hpp"

struct hid_device_;

namespace cathbox::device {

struct HidDeviceInfo {
  std::string path;     // hidraw node, e.g. /dev/hidraw3
  std::string serial;
  std::string product;
  uint16_t vid = 0;
  uint16_t pid = 0;
};

class HidapiTransport final : public Transport {
 public:
  // Every attached box (VID:PID from protocol/).
  [[nodiscard]] static Result<std::vector<HidDeviceInfo>> enumerate();
  // Opens the box at `path`, or the first box found when path is empty.
  [[nodiscard]] static Result<std::unique_ptr<HidapiTransport>> open(const std::string& path);
  ~HidapiTransport() override;
  HidapiTransport(const HidapiTransport&) = delete;
  HidapiTransport& operator=(const HidapiTransport&) = delete;

  [[nodiscard]] IoStatus read_in(Report& report) override;
  [[nodiscard]] IoStatus write_out(const Report& report) override;
  [[nodiscard]] Status get_feature(uint8_t id, Report& report) override;
  [[nodiscard]] Status set_feature(const Report& report) override;
  [[nodiscard]] std::string describe() const override;

 private:
  HidapiTransport(hid_device_* device, hid_device_* writer_device, std::string path);
  void writer_loop();

  hid_device_* device_;         // reads and feature reports: the caller's thread only
  hid_device_* writer_device_;  // interrupt OUT writes: the writer thread only
  std::string path_;
  std::mutex mutex_;  // guards the mailbox and the failure flag
  std::condition_variable wake_;
  Report mailbox_{};
  bool mailbox_full_ = false;
  bool stop_ = false;
  bool failed_ = false;
  std::thread writer_;
};

}  // namespace cathbox::device
