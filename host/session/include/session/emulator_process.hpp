#pragma once
// cathbox-emu as a child process on a socket of its own, for a program that finds no box
// (the trainer, `cathbox session run --emu` without a path); stopped (SIGTERM, then waited for)
// when destroyed.
#include <sys/types.h>

#include <memory>
#include <string>
#include <vector>

#include "base/result.hpp"

namespace cathbox::session {

class EmulatorProcess {
 public:
  // Starts `program --socket socket [extra...]`; else the error line.
  [[nodiscard]] static base::Result<std::unique_ptr<EmulatorProcess>> start(const std::string& program,
                                                                            const std::string& socket,
                                                                            const std::vector<std::string>& extra);
  ~EmulatorProcess();
  EmulatorProcess(const EmulatorProcess&) = delete;
  EmulatorProcess& operator=(const EmulatorProcess&) = delete;
  [[nodiscard]] bool running() const;
  [[nodiscard]] const std::string& socket() const { return socket_; }

 private:
  EmulatorProcess(pid_t pid, std::string socket) : pid_(pid), socket_(std::move(socket)) {}
  pid_t pid_;
  std::string socket_;
};

}  // namespace cathbox::session
