#pragma once
// The emulator's side of the socket transport (protocol/README.md, "Emulator socket
// transport"): a listening Unix-domain SOCK_SEQPACKET socket, up to kMaxClients connections
// (like several programs opening one hidraw node: each gets every IN report, any may send),
// frames decoded and handed to a Handler. Never blocks: a client that does not read loses IN
// reports, as a USB host that does not poll would. A control reply is never lost that way: if
// the client's queue is full it is kept and sent first at the next poll (endpoint 0 does not
// queue behind interrupt IN), and that client gets no IN report and no new request is taken
// from it until it went out.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "emu/result.hpp"
#include "protocol/cbx_emu_frame.h"

namespace cathbox::emu {

struct ServerCounts {
  uint64_t malformed = 0;     // datagrams that were not valid host-to-device frames
  uint64_t in_sent = 0;
  uint64_t in_dropped = 0;    // a client's queue was full
  uint64_t out_received = 0;
  uint64_t controls = 0;
  uint64_t stalls = 0;
  uint64_t connections = 0;
};

class EmuServer {
 public:
  static constexpr size_t kMaxClients = 4;
  class Handler {
   public:
    virtual ~Handler() = default;
    // What is attached now; false = nothing enumerates (connections are closed at once).
    [[nodiscard]] virtual bool attached(uint16_t& vid, uint16_t& pid) = 0;
    virtual void on_out(std::span<const uint8_t> report) = 0;
    // Returns false to stall; reply holds the IN data stage.
    [[nodiscard]] virtual bool on_control(const cbx_usb_setup& setup, std::span<const uint8_t> data,
                                          std::vector<uint8_t>& reply) = 0;
  };

  // Binds path (replacing a stale socket file nobody listens on).
  [[nodiscard]] static Result<std::unique_ptr<EmuServer>> listen(const std::string& path, Handler& handler);
  ~EmuServer();
  EmuServer(const EmuServer&) = delete;
  EmuServer& operator=(const EmuServer&) = delete;

  // Accepts new connections and handles every pending datagram.
  void poll();
  // Sends one IN report to every client.
  void send_in(std::span<const uint8_t> report);
  // Closes every connection (the device detached).
  void detach();
  [[nodiscard]] const std::string& path() const { return path_; }
  [[nodiscard]] size_t clients() const;
  // Descriptors to wait on (listening socket and clients).
  [[nodiscard]] std::vector<int> fds() const;
  [[nodiscard]] const ServerCounts& counts() const { return counts_; }

 private:
  EmuServer(int fd, std::string path, Handler& handler);
  void accept_all();
  void serve(size_t slot);
  bool answer_control(size_t slot, const cbx_emu_frame& frame);
  void close_client(size_t slot);
  bool send_frame(int fd, const cbx_emu_frame& frame);
  // Sends a held-back control reply; false while the client's queue is still full.
  bool flush_reply(size_t slot);

  int listen_fd_;
  std::string path_;
  Handler& handler_;
  std::array<int, kMaxClients> clients_;
  ServerCounts counts_;
  std::vector<uint8_t> rx_;
  std::vector<uint8_t> tx_;
  std::vector<uint8_t> reply_;
  std::array<std::vector<uint8_t>, kMaxClients> held_reply_;  // encoded, waiting for queue space
};

}  // namespace cathbox::emu
