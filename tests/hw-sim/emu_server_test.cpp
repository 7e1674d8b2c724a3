// EmuServer on a real socket: a control reply reaches a client whose receive queue was full of
// IN reports (as USB, where endpoint 0 does not queue behind interrupt IN).
#include <gtest/gtest.h>
#include <sys/socket.h>
#include <sys/un.h>
#include <unistd.h>

#include <array>
#include <cstring>
#include <string>

#include "emu/emu_server.hpp"
#include "protocol/cbx_protocol.h"

namespace cathbox::emu {
namespace {

class EchoHandler final : public EmuServer::Handler {
 public:
  bool attached(uint16_t& vid, uint16_t& pid) override {
    vid = CBX_USB_VID;
    pid = CBX_USB_PID;
    return true;
  }
  void on_out(std::span<const uint8_t>) override {}
  bool on_control(const cbx_usb_setup& setup, std::span<const uint8_t>, std::vector<uint8_t>& reply) override {
    ++controls;
    reply.assign(setup.length, 0xA5);
    return true;
  }
  int controls = 0;
};

// Reads every pending datagram; counts IN reports and replies carrying `tag`.
void drain(int fd, int& ins, int& replies, uint16_t tag) {
  std::array<uint8_t, CBX_EMU_FRAME_MAX + 1> buf{};
  for (;;) {
    const ssize_t n = ::recv(fd, buf.data(), buf.size(), MSG_DONTWAIT);
    if (n <= 0) return;
    cbx_emu_frame f;
    if (cbx_emu_frame_decode(buf.data(), static_cast<size_t>(n), &f) != CBX_OK) continue;
    if (f.kind == CBX_EMU_IN) ++ins;
    if (f.kind == CBX_EMU_CONTROL_REPLY && f.tag == tag && f.status == CBX_EMU_STATUS_OK && f.data_length == 64) ++replies;
  }
}

TEST(EmuServer, AControlReplyIsNotLostBehindAFullQueueOfInReports) {
  EchoHandler handler;
  const std::string path = "/tmp/cathbox-test-server-" + std::to_string(::getpid()) + ".sock";
  auto server = EmuServer::listen(path, handler);
  ASSERT_TRUE(server.ok()) << server.error().message;
  const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET, 0);
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  std::strncpy(addr.sun_path, path.c_str(), sizeof addr.sun_path - 1);
  ASSERT_EQ(::connect(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr), 0);
  server.value()->poll();  // accepts and says hello
  ASSERT_EQ(server.value()->clients(), 1u);

  // The client stops reading (a prompt waiting for Enter) until IN reports are dropped.
  const std::array<uint8_t, 64> report{};
  for (int i = 0; i < 100'000 && server.value()->counts().in_dropped == 0; ++i) server.value()->send_in(report);
  ASSERT_GT(server.value()->counts().in_dropped, 0u);

  // Then it asks for a feature report, and the server handles it before the client drains.
  std::array<uint8_t, CBX_EMU_FRAME_MAX> tx{};
  cbx_emu_frame request{};
  request.kind = CBX_EMU_CONTROL;
  request.tag = 77;
  request.setup = {0xA1, 0x01, 0x0310, 0, 64};
  const int n = cbx_emu_frame_encode(&request, tx.data(), tx.size());
  ASSERT_GT(n, 0);
  ASSERT_EQ(::send(fd, tx.data(), static_cast<size_t>(n), 0), n);
  server.value()->poll();
  EXPECT_EQ(handler.controls, 1);
  int ins = 0;
  int replies = 0;
  drain(fd, ins, replies, 77);  // the client waits for its reply: it reads what queued up
  EXPECT_GT(ins, 0);
  for (int frame = 0; frame < 3 && replies == 0; ++frame) {
    server.value()->send_in(report);  // the next USB frames
    server.value()->poll();
    drain(fd, ins, replies, 77);
  }
  EXPECT_EQ(replies, 1);
  EXPECT_EQ(handler.controls, 1);
  ::close(fd);
}

}  // namespace
}  // namespace cathbox::emu
