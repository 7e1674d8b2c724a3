#include "emu/emu_server.hpp"

#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

namespace cathbox::emu {

Result<std::unique_ptr<EmuServer>> EmuServer::listen(const std::string& path, Handler& handler) {
  sockaddr_un addr{};
  addr.sun_family = AF_UNIX;
  if (path.empty() || path.size() >= sizeof addr.sun_path) return Error{"socket path '" + path + "' is empty or too long"};
  std::memcpy(addr.sun_path, path.c_str(), path.size() + 1);
  const int fd = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
  if (fd < 0) return Error{std::string("socket(): ") + std::strerror(errno)};
  struct stat st {};
  if (::lstat(path.c_str(), &st) == 0) {
    if (!S_ISSOCK(st.st_mode)) {
      ::close(fd);
      return Error{path + " exists and is not a socket"};
    }
    const int probe = ::socket(AF_UNIX, SOCK_SEQPACKET | SOCK_CLOEXEC, 0);
    const bool live = probe >= 0 && ::connect(probe, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) == 0;
    if (probe >= 0) ::close(probe);
    if (live) {
      ::close(fd);
      return Error{"another emulator is listening at " + path};
    }
    ::unlink(path.c_str());
  }
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&addr), sizeof addr) != 0 || ::listen(fd, 8) != 0) {
    const int err = errno;
    ::close(fd);
    return Error{"cannot listen at " + path + ": " + std::strerror(err)};
  }
  return std::unique_ptr<EmuServer>(new EmuServer(fd, path, handler));
}

EmuServer::EmuServer(int fd, std::string path, Handler& handler)
    : listen_fd_(fd), path_(std::move(path)), handler_(handler), rx_(CBX_EMU_FRAME_MAX + 1), tx_(CBX_EMU_FRAME_MAX) {
  clients_.fill(-1);
}

EmuServer::~EmuServer() {
  detach();
  ::close(listen_fd_);
  ::unlink(path_.c_str());
}

size_t EmuServer::clients() const {
  size_t n = 0;
  for (const int c : clients_) n += c >= 0 ? 1u : 0u;
  return n;
}

std::vector<int> EmuServer::fds() const {
  std::vector<int> out{listen_fd_};
  for (const int c : clients_) {
    if (c >= 0) out.push_back(c);
  }
  return out;
}

bool EmuServer::send_frame(int fd, const cbx_emu_frame& frame) {
  const int n = cbx_emu_frame_encode(&frame, tx_.data(), tx_.size());
  if (n < 0) return false;
  return ::send(fd, tx_.data(), static_cast<size_t>(n), MSG_DONTWAIT | MSG_NOSIGNAL) == n;
}

void EmuServer::accept_all() {
  for (;;) {
    const int fd = ::accept4(listen_fd_, nullptr, nullptr, SOCK_NONBLOCK | SOCK_CLOEXEC);
    if (fd < 0) return;
    uint16_t vid = 0;
    uint16_t pid = 0;
    size_t slot = kMaxClients;
    for (size_t i = 0; i < kMaxClients; ++i) {
      if (clients_[i] < 0) {
        slot = i;
        break;
      }
    }
    if (slot == kMaxClients || !handler_.attached(vid, pid)) {
      ::close(fd);  // nothing enumerates, or too many programs have the box open
      continue;
    }
    const cbx_emu_hello hello{vid, pid};
    const int n = cbx_emu_hello_encode(&hello, tx_.data(), tx_.size());
    if (n < 0 || ::send(fd, tx_.data(), static_cast<size_t>(n), MSG_DONTWAIT | MSG_NOSIGNAL) != n) {
      ::close(fd);
      continue;
    }
    clients_[slot] = fd;
    ++counts_.connections;
  }
}

void EmuServer::close_client(size_t slot) {
  if (clients_[slot] >= 0) ::close(clients_[slot]);
  clients_[slot] = -1;
  held_reply_[slot].clear();
}

bool EmuServer::flush_reply(size_t slot) {
  auto& held = held_reply_[slot];
  if (held.empty()) return true;
  const ssize_t n = ::send(clients_[slot], held.data(), held.size(), MSG_DONTWAIT | MSG_NOSIGNAL);
  if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return false;
  if (n < 0) {
    close_client(slot);
    return false;
  }
  held.clear();
  return true;
}

void EmuServer::detach() {
  for (size_t i = 0; i < kMaxClients; ++i) close_client(i);
}

// A control transfer: the handler's answer, sent back tagged (held if the client's queue is
// full). False when the client is gone (closed on a send error, or the handler detached).
bool EmuServer::answer_control(size_t slot, const cbx_emu_frame& frame) {
  ++counts_.controls;
  const int fd = clients_[slot];
  const bool ok = handler_.on_control(frame.setup, {frame.data, frame.data_length}, reply_);
  if (ok && reply_.size() > frame.setup.length) reply_.resize(frame.setup.length);
  cbx_emu_frame answer{};
  answer.kind = CBX_EMU_CONTROL_REPLY;
  answer.status = ok ? CBX_EMU_STATUS_OK : CBX_EMU_STATUS_STALL;
  answer.tag = frame.tag;
  answer.data = ok && !reply_.empty() ? reply_.data() : nullptr;
  answer.data_length = ok ? reply_.size() : 0u;
  if (!ok) ++counts_.stalls;
  const int length = cbx_emu_frame_encode(&answer, tx_.data(), tx_.size());
  if (length > 0 && ::send(fd, tx_.data(), static_cast<size_t>(length), MSG_DONTWAIT | MSG_NOSIGNAL) < 0) {
    if (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR) {
      held_reply_[slot].assign(tx_.begin(), tx_.begin() + length);  // the client's queue is full
    } else {
      close_client(slot);
      return false;
    }
  }
  return clients_[slot] >= 0;
}

void EmuServer::serve(size_t slot) {
  for (int budget = 0; budget < 64 && clients_[slot] >= 0 && held_reply_[slot].empty(); ++budget) {
    const int fd = clients_[slot];
    const ssize_t n = ::recv(fd, rx_.data(), rx_.size(), MSG_DONTWAIT);
    if (n < 0 && (errno == EAGAIN || errno == EWOULDBLOCK)) return;
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      close_client(slot);
      return;
    }
    cbx_emu_frame frame;
    if (cbx_emu_frame_decode(rx_.data(), static_cast<size_t>(n), &frame) != CBX_OK) {
      ++counts_.malformed;
      continue;
    }
    if (frame.kind == CBX_EMU_OUT) {
      ++counts_.out_received;
      handler_.on_out({frame.data, frame.data_length});
    } else if (frame.kind == CBX_EMU_CONTROL) {
      // The handler may have detached the device (bootloader entry/exit) after replying.
      if (!answer_control(slot, frame)) return;
    } else {
      ++counts_.malformed;  // device-to-host kinds are not valid from a host
    }
  }
}

void EmuServer::poll() {
  accept_all();
  for (size_t i = 0; i < kMaxClients; ++i) {
    if (clients_[i] >= 0 && flush_reply(i)) serve(i);
  }
}

void EmuServer::send_in(std::span<const uint8_t> report) {
  cbx_emu_frame frame{};
  frame.kind = CBX_EMU_IN;
  frame.data = report.data();
  frame.data_length = report.size();
  for (size_t i = 0; i < kMaxClients; ++i) {
    if (clients_[i] < 0) continue;
    if (!held_reply_[i].empty()) {
      ++counts_.in_dropped;  // the queue space is the reply's
      continue;
    }
    if (send_frame(clients_[i], frame)) {
      ++counts_.in_sent;
    } else if (errno == EAGAIN || errno == EWOULDBLOCK) {
      ++counts_.in_dropped;
    } else {
      close_client(i);
    }
  }
}

}  // namespace cathbox::emu
