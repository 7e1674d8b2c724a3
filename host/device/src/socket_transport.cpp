#include "device/socket_transport.hpp"

#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include "protocol/cbx_emu_frame.h"
#include "protocol/cbx_usb_requests.h"

namespace cathbox::device {
namespace {
uint16_t feature_value(uint8_t id) { return static_cast<uint16_t>((CBX_USB_HID_REPORT_FEATURE << 8) | id); }
}  // namespace

std::string SocketTransport::default_path() {
  char path[sizeof(sockaddr_un::sun_path)];
  if (cbx_emu_default_socket_path(path, sizeof path) != CBX_OK) return "/tmp/cathbox-emu.sock";
  return path;
}

Result<std::unique_ptr<SocketTransport>> SocketTransport::open(const std::string& path, Clock& clock,
                                                               uint64_t timeout_us) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof addr.sun_path) {
    return make_error(Errc::kBadArgument, "emulator socket path '" + path + "' is empty or too long");
  }
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return make_error(Errc::kIo, std::string("socket(): ") + std::strerror(errno));
  if (::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0) {
    const int err = errno;
    ::close(fd);
    return make_error(Errc::kNoDevice, "no emulator at " + path + ": " + std::strerror(err));
  }
  std::unique_ptr<SocketTransport> t(new SocketTransport(fd, path, clock, timeout_us));
  const std::int64_t deadline = clock.now_us() + static_cast<std::int64_t>(timeout_us);
  for (;;) {
    const Rx rx = t->receive();
    if (rx == Rx::kHello) return t;
    if (rx == Rx::kClosed) return make_error(Errc::kDisconnected, "emulator at " + path + " closed the connection");
    if (rx == Rx::kNone) {
      if (clock.now_us() >= deadline) return make_error(Errc::kTimeout, "emulator at " + path + " sent no hello");
      clock.wait(fd, deadline - clock.now_us());
    }
  }
}

SocketTransport::SocketTransport(int fd, std::string path, Clock& clock, uint64_t timeout_us)
    : fd_(fd), path_(std::move(path)), clock_(clock), timeout_us_(timeout_us),
      rx_(CBX_EMU_FRAME_MAX + 1), reply_data_(CBX_EMU_CONTROL_DATA_MAX), tx_(CBX_EMU_FRAME_MAX) {}

SocketTransport::~SocketTransport() { ::close(fd_); }

SocketTransport::Rx SocketTransport::receive() {
  if (closed_) return Rx::kClosed;
  for (;;) {
    const ssize_t n = ::recv(fd_, rx_.data(), rx_.size(), MSG_DONTWAIT);
    if (n < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN || errno == EWOULDBLOCK) return Rx::kNone;
      closed_ = true;
      return Rx::kClosed;
    }
    if (n == 0) {  // orderly shutdown: the emulator stopped or detached
      closed_ = true;
      return Rx::kClosed;
    }
    cbx_emu_frame frame;
    if (cbx_emu_frame_decode(rx_.data(), static_cast<size_t>(n), &frame) != CBX_OK) continue;  // not a frame
    switch (frame.kind) {
      case CBX_EMU_HELLO: {
        cbx_emu_hello hello;
        if (cbx_emu_hello_decode(&frame, &hello) != CBX_OK) continue;
        vid_ = hello.vid;
        pid_ = hello.pid;
        return Rx::kHello;
      }
      case CBX_EMU_IN:
        std::copy_n(frame.data, kReportSize, last_in_.begin());
        return Rx::kIn;
      case CBX_EMU_CONTROL_REPLY:
        reply_status_ = frame.status;
        reply_tag_ = frame.tag;
        reply_data_.assign(frame.data, frame.data + frame.data_length);
        return Rx::kReply;
      default:  // host-bound kinds only; anything else is a peer bug, dropped
        continue;
    }
  }
}

IoStatus SocketTransport::read_in(Report& report) {
  if (has_pending_in_) {
    report = pending_in_;
    has_pending_in_ = false;
    return IoStatus::kOk;
  }
  for (;;) {
    switch (receive()) {
      case Rx::kIn: report = last_in_; return IoStatus::kOk;
      case Rx::kNone: return IoStatus::kEmpty;
      case Rx::kClosed: return IoStatus::kDisconnected;
      case Rx::kReply: continue;  // a reply that arrived after its timeout
      case Rx::kHello: continue;
    }
  }
}

IoStatus SocketTransport::write_out(const Report& report) {
  if (closed_) return IoStatus::kDisconnected;
  cbx_emu_frame frame{};
  frame.kind = CBX_EMU_OUT;
  frame.data = report.data();
  frame.data_length = report.size();
  const int length = cbx_emu_frame_encode(&frame, tx_.data(), tx_.size());
  if (length < 0) return IoStatus::kEmpty;
  for (;;) {
    const ssize_t n = ::send(fd_, tx_.data(), static_cast<size_t>(length), MSG_DONTWAIT | MSG_NOSIGNAL);
    if (n >= 0) return IoStatus::kOk;
    if (errno == EINTR) continue;
    if (errno == EAGAIN || errno == EWOULDBLOCK) return IoStatus::kEmpty;
    closed_ = true;
    return IoStatus::kDisconnected;
  }
}

Result<size_t> SocketTransport::transfer(const UsbSetup& setup, uint16_t length, std::span<const uint8_t> out,
                                         std::span<uint8_t> in) {
  if (closed_) return make_error(Errc::kDisconnected, "emulator at " + path_ + " is gone");
  cbx_emu_frame frame{};
  frame.kind = CBX_EMU_CONTROL;
  frame.tag = next_tag_++;
  if (next_tag_ == 0) next_tag_ = 1;
  frame.setup = {setup.request_type, setup.request, setup.value, setup.index, length};
  frame.data = out.empty() ? nullptr : out.data();
  frame.data_length = out.size();
  const int n = cbx_emu_frame_encode(&frame, tx_.data(), tx_.size());
  if (n < 0) return make_error(Errc::kBadArgument, "control transfer of " + std::to_string(length) + " bytes does not fit a frame");
  if (::send(fd_, tx_.data(), static_cast<size_t>(n), MSG_NOSIGNAL) < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK) {
      return make_error(Errc::kTimeout, "emulator at " + path_ + " is not reading its socket");
    }
    closed_ = true;
    return make_error(Errc::kDisconnected, "emulator at " + path_ + ": send: " + std::strerror(errno));
  }
  const std::int64_t deadline = clock_.now_us() + static_cast<std::int64_t>(timeout_us_);
  for (;;) {
    const Rx rx = receive();
    switch (rx) {
      case Rx::kReply:
        if (reply_tag_ != frame.tag) continue;  // stale reply to an earlier, timed-out request
        if (reply_status_ != CBX_EMU_STATUS_OK) {
          return make_error(Errc::kStall, "device stalled request 0x" + std::to_string(setup.request));
        }
        if (reply_data_.size() > in.size()) return make_error(Errc::kIo, "control reply longer than wLength");
        std::copy(reply_data_.begin(), reply_data_.end(), in.begin());
        return reply_data_.size();
      case Rx::kIn:
        pending_in_ = last_in_;
        has_pending_in_ = true;
        continue;
      case Rx::kHello: continue;
      case Rx::kClosed: return make_error(Errc::kDisconnected, "emulator at " + path_ + " closed the connection");
      case Rx::kNone: break;
    }
    const std::int64_t now = clock_.now_us();
    if (now >= deadline) return make_error(Errc::kTimeout, "emulator at " + path_ + ": no reply to a control request");
    clock_.wait(fd_, deadline - now);
  }
}

Status SocketTransport::get_feature(uint8_t id, Report& report) {
  const UsbSetup setup{CBX_USB_HID_GET_TYPE, CBX_USB_HID_GET_REPORT, feature_value(id), 0};
  auto got = transfer(setup, kReportSize, {}, report);
  if (!got) return got.error();
  if (got.value() != kReportSize) return make_error(Errc::kBadReport, "feature report 0x" + std::to_string(id) + " is " + std::to_string(got.value()) + " bytes, not 64");
  return Ok{};
}

Status SocketTransport::set_feature(const Report& report) {
  const UsbSetup setup{CBX_USB_HID_SET_TYPE, CBX_USB_HID_SET_REPORT, feature_value(report[0]), 0};
  auto done = transfer(setup, kReportSize, report, {});
  if (!done) return done.error();
  return Ok{};
}

Status SocketTransport::control_out(const UsbSetup& setup, std::span<const uint8_t> data) {
  if (data.size() > CBX_EMU_CONTROL_DATA_MAX) return make_error(Errc::kBadArgument, "control data stage too long");
  auto done = transfer(setup, static_cast<uint16_t>(data.size()), data, {});
  if (!done) return done.error();
  return Ok{};
}

Result<size_t> SocketTransport::control_in(const UsbSetup& setup, std::span<uint8_t> in) {
  if (in.size() > CBX_EMU_CONTROL_DATA_MAX) return make_error(Errc::kBadArgument, "control data stage too long");
  return transfer(setup, static_cast<uint16_t>(in.size()), {}, in);
}

Result<std::string> SocketTransport::alt_name(uint8_t alt) {
  // Standard GET_DESCRIPTOR(STRING); the emulated bootloader names alternate setting N with
  // string index 4 + N (host/device/README.md).
  std::array<uint8_t, 255> raw{};
  const UsbSetup setup{0x80, 0x06, static_cast<uint16_t>(0x0300u | (4u + alt)), 0x0409};
  auto got = transfer(setup, raw.size(), {}, raw);
  if (!got) return got.error();
  const size_t n = got.value();
  if (n < 2 || raw[1] != 0x03 || raw[0] != n || (n % 2) != 0) return make_error(Errc::kDeviceError, "bad string descriptor");
  std::string text;
  for (size_t i = 2; i + 1 < n; i += 2) text.push_back(raw[i + 1] == 0 && raw[i] < 0x80 ? static_cast<char>(raw[i]) : '?');
  return text;
}

void SocketTransport::delay(uint64_t max_us) {
  const std::int64_t deadline = clock_.now_us() + static_cast<std::int64_t>(max_us);
  for (std::int64_t now = clock_.now_us(); now < deadline; now = clock_.now_us()) clock_.wait(-1, deadline - now);
}

std::string SocketTransport::describe() const {
  char id[16];
  std::snprintf(id, sizeof id, "%04x:%04x", vid_, pid_);
  return std::string("emulator ") + id + " " + path_;
}

}  // namespace cathbox::device
