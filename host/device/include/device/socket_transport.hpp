#pragma once
// The emulator's transport: a Unix-domain SOCK_SEQPACKET connection to cathbox-emu carrying the
// same report bytes as USB, framed as in protocol/include/protocol/cbx_emu_frame.h. It is both
// a Transport (the application's HID interface) and a ControlTransfer (the emulated DfuSe
// bootloader on endpoint 0). Not thread-safe: one thread uses it.
#include <memory>
#include <string>
#include <vector>

#include "device/clock.hpp"
#include "device/control_transfer.hpp"
#include "device/transport.hpp"

namespace cathbox::device {

class SocketTransport final : public Transport, public ControlTransfer {
 public:
  // Connects and waits (up to timeout_us on clock) for the emulator's HELLO, which says what is
  // attached: the application (1209:CB01) or the DfuSe bootloader (0483:DF11).
  [[nodiscard]] static Result<std::unique_ptr<SocketTransport>> open(const std::string& path, Clock& clock,
                                                                     uint64_t timeout_us = 200'000);
  // The default path (cbx_emu_default_socket_path).
  [[nodiscard]] static std::string default_path();
  ~SocketTransport() override;
  SocketTransport(const SocketTransport&) = delete;
  SocketTransport& operator=(const SocketTransport&) = delete;

  [[nodiscard]] uint16_t vid() const { return vid_; }
  [[nodiscard]] uint16_t pid() const { return pid_; }
  [[nodiscard]] int fd() const { return fd_; }

  [[nodiscard]] IoStatus read_in(Report& report) override;
  [[nodiscard]] IoStatus write_out(const Report& report) override;
  [[nodiscard]] Status get_feature(uint8_t id, Report& report) override;
  [[nodiscard]] Status set_feature(const Report& report) override;
  [[nodiscard]] std::string describe() const override;

  [[nodiscard]] Status control_out(const UsbSetup& setup, std::span<const uint8_t> data) override;
  [[nodiscard]] Result<size_t> control_in(const UsbSetup& setup, std::span<uint8_t> in) override;
  [[nodiscard]] Result<std::string> alt_name(uint8_t alt) override;
  void delay(uint64_t max_us) override;

 private:
  SocketTransport(int fd, std::string path, Clock& clock, uint64_t timeout_us);
  enum class Rx { kNone, kIn, kReply, kHello, kClosed };
  // Receives one datagram without blocking and sorts it.
  Rx receive();
  [[nodiscard]] Result<size_t> transfer(const UsbSetup& setup, uint16_t length, std::span<const uint8_t> out,
                                        std::span<uint8_t> in);

  int fd_;
  std::string path_;
  Clock& clock_;
  uint64_t timeout_us_;
  uint16_t vid_ = 0;
  uint16_t pid_ = 0;
  uint16_t next_tag_ = 1;
  bool closed_ = false;
  // The newest IN report seen while waiting for a control reply (kept for read_in).
  Report pending_in_{};
  bool has_pending_in_ = false;
  // Last received frame's parts.
  Report last_in_{};
  uint8_t reply_status_ = 0;
  uint16_t reply_tag_ = 0;
  std::vector<uint8_t> rx_;         // one datagram (sized once, at open)
  std::vector<uint8_t> reply_data_;  // data stage of the last reply
  std::vector<uint8_t> tx_;
};

}  // namespace cathbox::device
