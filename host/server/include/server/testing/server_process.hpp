#pragma once
// cathbox-server as a child process (the program the centre runs), for fault tests and the
// benchmark: started on a loopback port, killed with any signal, restarted on the same port.
#include <cstdint>
#include <string>
#include <vector>

#include "server/testing/child_process.hpp"

namespace cathbox::server::testing {

class ServerProcess {
 public:
  // `port` 0 takes a free one (then reused by restart()). Waits for the "listening" line.
  // The program is build/<preset>/bin/cathbox-server beside the running executable.
  ServerProcess(std::string db_url, std::uint16_t port = 0, std::vector<std::string> extra_args = {});
  ~ServerProcess();
  void kill(int sig);   // and reap
  void restart();       // same database, same port
  [[nodiscard]] bool alive();
  // https:// when extra_args hold --tls-cert.
  [[nodiscard]] std::string base_url() const { return scheme() + "://127.0.0.1:" + std::to_string(port_); }
  [[nodiscard]] std::string scheme() const;
  [[nodiscard]] std::uint16_t port() const { return port_; }
  [[nodiscard]] pid_t pid() const { return child_.pid(); }

 private:
  void start();
  std::string db_url_;
  std::uint16_t port_;
  std::vector<std::string> extra_;
  ChildProcess child_;
};

}  // namespace cathbox::server::testing
