#include "server/testing/server_process.hpp"

#include <signal.h>
#include <sys/wait.h>

#include <algorithm>
#include <stdexcept>

namespace cathbox::server::testing {

std::string ServerProcess::scheme() const {
  return std::find(extra_.begin(), extra_.end(), "--tls-cert") == extra_.end() ? "http" : "https";
}

ServerProcess::ServerProcess(std::string db_url, std::uint16_t port, std::vector<std::string> extra_args)
    : db_url_(std::move(db_url)), port_(port), extra_(std::move(extra_args)) {
  start();
}

ServerProcess::~ServerProcess() {
  if (child_.running()) {
    child_.signal(SIGTERM);
    (void)child_.wait();
  }
}

void ServerProcess::start() {
  std::vector<std::string> argv = {sibling_program("cathbox-server"), "--db", db_url_, "--listen",
                                   "127.0.0.1:" + std::to_string(port_), "--web", CATHBOX_SERVER_WEB_DIR};
  argv.insert(argv.end(), extra_.begin(), extra_.end());
  ChildOptions o;
  o.capture_stdout = true;
  if (const std::string e = child_.start(argv, o); !e.empty()) throw std::runtime_error("cathbox-server: " + e);
  const std::optional<std::string> line = child_.read_line();
  const std::string prefix = "cathbox-server: listening on " + scheme() + "://127.0.0.1:";
  if (!line || line->rfind(prefix, 0) != 0) {
    const int rc = child_.wait();
    throw std::runtime_error("cathbox-server did not start (exit " + std::to_string(rc) + "): " + line.value_or("no output"));
  }
  port_ = static_cast<std::uint16_t>(std::stoi(line->substr(prefix.size())));
}

void ServerProcess::kill(int sig) {
  child_.signal(sig);
  (void)child_.wait();
}

void ServerProcess::restart() {
  if (child_.running()) kill(SIGKILL);
  start();
}

bool ServerProcess::alive() {
  if (!child_.running()) return false;
  int status = 0;
  return ::waitpid(child_.pid(), &status, WNOHANG) == 0;
}

}  // namespace cathbox::server::testing
