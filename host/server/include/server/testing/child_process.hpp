#pragma once
// A child process for tests and benchmarks: started with an argument vector (no shell),
// optionally as another user, stdout readable line by line, stopped by signal, always reaped.
#include <optional>
#include <string>
#include <sys/types.h>
#include <vector>

namespace cathbox::server::testing {

struct ChildOptions {
  std::optional<uid_t> uid;  // run as this user (and gid), when the caller is root
  std::optional<gid_t> gid;
  bool capture_stdout = false;
  std::string stdout_file;  // else: append stdout and stderr here ("" = inherit stderr, stdout to /dev/null)
};

class ChildProcess {
 public:
  ChildProcess() = default;
  ChildProcess(const ChildProcess&) = delete;
  ChildProcess& operator=(const ChildProcess&) = delete;
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&& other) noexcept;
  // Kills (SIGKILL) and reaps a child still running.
  ~ChildProcess();

  // Empty string on success, else why not.
  [[nodiscard]] std::string start(const std::vector<std::string>& argv, const ChildOptions& options = {});
  // The next line of the child's stdout (without '\n'); nullopt at end of output.
  [[nodiscard]] std::optional<std::string> read_line();
  void signal(int sig);
  // Waits for exit; the exit code, or 128 + signal.
  int wait();
  [[nodiscard]] pid_t pid() const { return pid_; }
  [[nodiscard]] bool running() const { return pid_ > 0; }

 private:
  pid_t pid_ = -1;
  int out_fd_ = -1;
  std::string buffer_;
};

// Runs argv to completion; exit code (or 128 + signal), output appended to `log` if given.
int run_process(const std::vector<std::string>& argv, const ChildOptions& options = {});

// The path of a program next to the running executable (build/<preset>/bin/NAME).
[[nodiscard]] std::string sibling_program(const std::string& name);

}  // namespace cathbox::server::testing
