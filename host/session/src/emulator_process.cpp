#include "session/emulator_process.hpp"

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstring>

extern char** environ;

namespace cathbox::session {

base::Result<std::unique_ptr<EmulatorProcess>> EmulatorProcess::start(const std::string& program,
                                                                      const std::string& socket,
                                                                      const std::vector<std::string>& extra) {
  std::vector<std::string> args = {program, "--socket", socket};
  args.insert(args.end(), extra.begin(), extra.end());
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  const int rc = posix_spawn(&pid, program.c_str(), nullptr, nullptr, argv.data(), environ);
  if (rc != 0) return base::Error{program + ": cannot start the emulated box: " + std::strerror(rc)};
  return std::unique_ptr<EmulatorProcess>(new EmulatorProcess(pid, socket));
}

EmulatorProcess::~EmulatorProcess() {
  kill(pid_, SIGTERM);
  int status = 0;
  waitpid(pid_, &status, 0);
  unlink(socket_.c_str());
}

bool EmulatorProcess::running() const {
  int status = 0;
  return waitpid(pid_, &status, WNOHANG) == 0;
}

}  // namespace cathbox::session
