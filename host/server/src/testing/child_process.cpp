#include "server/testing/child_process.hpp"

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <grp.h>

namespace cathbox::server::testing {

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : pid_(other.pid_), out_fd_(other.out_fd_), buffer_(std::move(other.buffer_)) {
  other.pid_ = -1;
  other.out_fd_ = -1;
}

ChildProcess& ChildProcess::operator=(ChildProcess&& other) noexcept {
  if (this != &other) {
    this->~ChildProcess();
    pid_ = other.pid_;
    out_fd_ = other.out_fd_;
    buffer_ = std::move(other.buffer_);
    other.pid_ = -1;
    other.out_fd_ = -1;
  }
  return *this;
}

ChildProcess::~ChildProcess() {
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    (void)wait();
  }
  if (out_fd_ >= 0) ::close(out_fd_);
  out_fd_ = -1;
}

std::string ChildProcess::start(const std::vector<std::string>& argv, const ChildOptions& options) {
  if (argv.empty()) return "no program";
  std::vector<char*> args;
  args.reserve(argv.size() + 1);
  for (const std::string& a : argv) args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  int pipe_fds[2] = {-1, -1};
  if (options.capture_stdout && ::pipe2(pipe_fds, O_CLOEXEC) != 0) return std::string("pipe: ") + std::strerror(errno);
  int log_fd = -1;
  if (!options.stdout_file.empty()) {
    log_fd = ::open(options.stdout_file.c_str(), O_WRONLY | O_CREAT | O_APPEND | O_CLOEXEC, 0644);
    if (log_fd < 0) return options.stdout_file + ": " + std::strerror(errno);
  }
  const int null_fd = ::open("/dev/null", O_RDWR | O_CLOEXEC);
  const pid_t pid = ::fork();
  if (pid < 0) return std::string("fork: ") + std::strerror(errno);
  if (pid == 0) {
    // Child: only async-signal-safe calls from here to exec.
    ::dup2(null_fd, 0);
    if (options.capture_stdout) {
      ::dup2(pipe_fds[1], 1);
    } else {
      ::dup2(log_fd >= 0 ? log_fd : null_fd, 1);
    }
    if (log_fd >= 0) ::dup2(log_fd, 2);
    if (options.gid && ::getuid() == 0) {
      ::setgroups(0, nullptr);
      if (::setgid(*options.gid) != 0) ::_exit(126);
    }
    if (options.uid && ::getuid() == 0 && ::setuid(*options.uid) != 0) ::_exit(126);
    ::execv(args[0], args.data());
    ::_exit(127);
  }
  if (pipe_fds[1] >= 0) ::close(pipe_fds[1]);
  if (log_fd >= 0) ::close(log_fd);
  ::close(null_fd);
  pid_ = pid;
  out_fd_ = pipe_fds[0];
  return {};
}

std::optional<std::string> ChildProcess::read_line() {
  if (out_fd_ < 0) return std::nullopt;
  for (;;) {
    const std::size_t nl = buffer_.find('\n');
    if (nl != std::string::npos) {
      std::string line = buffer_.substr(0, nl);
      buffer_.erase(0, nl + 1);
      return line;
    }
    char chunk[4096];
    const ssize_t n = ::read(out_fd_, chunk, sizeof chunk);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      if (buffer_.empty()) return std::nullopt;
      std::string line = std::move(buffer_);
      buffer_.clear();
      return line;
    }
    buffer_.append(chunk, static_cast<std::size_t>(n));
  }
}

void ChildProcess::signal(int sig) {
  if (pid_ > 0) ::kill(pid_, sig);
}

int ChildProcess::wait() {
  if (pid_ <= 0) return -1;
  int status = 0;
  while (::waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
  }
  pid_ = -1;
  if (WIFEXITED(status)) return WEXITSTATUS(status);
  if (WIFSIGNALED(status)) return 128 + WTERMSIG(status);
  return -1;
}

int run_process(const std::vector<std::string>& argv, const ChildOptions& options) {
  ChildProcess child;
  if (!child.start(argv, options).empty()) return 127;
  return child.wait();
}

std::string sibling_program(const std::string& name) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  return (self.parent_path() / name).string();
}

}  // namespace cathbox::server::testing
