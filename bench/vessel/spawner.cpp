#include "spawner.hpp"

#include <chrono>
#include <fstream>
#include <sstream>

#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace cathbox::bench {

void Spawner::start() {
  int to_child[2], from_child[2];
  if (pipe(to_child) != 0 || pipe(from_child) != 0) return;
  pid_ = fork();
  if (pid_ == 0) {
    close(to_child[1]);
    close(from_child[0]);
    serve(to_child[0], from_child[1]);
    _exit(0);
  }
  close(to_child[0]);
  close(from_child[1]);
  request_ = to_child[1];
  answer_ = from_child[0];
}

Run Spawner::run(const std::vector<std::string>& argv, const std::string& stdout_path) {
  Run run;
  std::string message = stdout_path + "\n";
  for (const std::string& a : argv) message += a + "\n";
  message += "\n";
  Result r{};
  if (request_ < 0 || write(request_, message.data(), message.size()) != static_cast<ssize_t>(message.size()) ||
      read(answer_, &r, sizeof r) != static_cast<ssize_t>(sizeof r)) {
    return run;
  }
  run.wall_s = r.wall_s;
  run.cpu_s = r.cpu_s;
  run.peak_bytes = r.peak_bytes;
  run.ok = r.ok != 0;
  std::ifstream in(stdout_path);
  std::getline(in, run.out);
  return run;
}

void Spawner::serve(int in, int out) {
  std::string buffer;
  char chunk[4096];
  for (;;) {
    const std::size_t end = buffer.find("\n\n");
    if (end == std::string::npos) {
      const ssize_t n = read(in, chunk, sizeof chunk);
      if (n <= 0) return;
      buffer.append(chunk, static_cast<std::size_t>(n));
      continue;
    }
    std::vector<std::string> fields;
    std::istringstream lines(buffer.substr(0, end));
    for (std::string line; std::getline(lines, line);) fields.push_back(line);
    buffer.erase(0, end + 2);
    Result r{};
    const auto start = std::chrono::steady_clock::now();
    const pid_t pid = fork();
    if (pid == 0) {
      const int fd = open(fields[0].c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (fd >= 0) dup2(fd, 1);
      std::vector<char*> args;
      for (std::size_t i = 1; i < fields.size(); ++i) args.push_back(fields[i].data());
      args.push_back(nullptr);
      execv(args[0], args.data());
      _exit(127);
    }
    int status = 0;
    rusage usage{};
    if (pid > 0 && wait4(pid, &status, 0, &usage) == pid) {
      r.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      r.cpu_s = static_cast<double>(usage.ru_utime.tv_sec + usage.ru_stime.tv_sec) +
                1e-6 * static_cast<double>(usage.ru_utime.tv_usec + usage.ru_stime.tv_usec);
      r.peak_bytes = 1024.0 * static_cast<double>(usage.ru_maxrss);
      r.ok = WIFEXITED(status) && WEXITSTATUS(status) == 0 ? 1 : 0;
    }
    if (write(out, &r, sizeof r) != static_cast<ssize_t>(sizeof r)) return;
  }
}

Spawner& spawner() {
  static Spawner s;
  return s;
}

}  // namespace cathbox::bench
