#include "server/testing/pg_cluster.hpp"

#include <fcntl.h>
#include <pwd.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "server/testing/child_process.hpp"

namespace cathbox::server::testing {

namespace fs = std::filesystem;

std::string PgCluster::bin_dir() {
  std::error_code ec;
  std::vector<fs::path> found;
  for (const auto& entry : fs::directory_iterator("/usr/lib/postgresql", ec)) {
    if (fs::exists(entry.path() / "bin" / "pg_ctl")) found.push_back(entry.path() / "bin");
  }
  if (found.empty()) return {};
  std::sort(found.begin(), found.end());
  return found.back().string();
}

int PgCluster::pg(const std::vector<std::string>& argv) const {
  ChildOptions o;
  if (as_postgres_) {
    o.uid = uid_;
    o.gid = gid_;
  }
  o.stdout_file = folder_ + "/tools.log";
  return run_process(argv, o);
}

Result<std::unique_ptr<PgCluster>> PgCluster::start(const PgClusterOptions& options) {
  std::unique_ptr<PgCluster> c(new PgCluster());
  c->options_ = options;
  c->bin_ = bin_dir();
  if (c->bin_.empty()) return make_error(503, "postgresql: no /usr/lib/postgresql/*/bin/pg_ctl (scripts/setup installs it)");
  if (::getuid() == 0) {
    const passwd* pw = ::getpwnam("postgres");
    if (pw == nullptr) return make_error(503, "postgresql: running as root and there is no 'postgres' user to run the server as");
    c->as_postgres_ = true;
    c->uid_ = pw->pw_uid;
    c->gid_ = pw->pw_gid;
  }
  char templ[] = "/tmp/cathbox-pg-XXXXXX";
  if (::mkdtemp(templ) == nullptr) return make_error(503, std::string("mkdtemp: ") + std::strerror(errno));
  c->folder_ = templ;
  if (c->as_postgres_ && ::chown(templ, c->uid_, c->gid_) != 0) {
    return make_error(503, std::string("chown ") + templ + ": " + std::strerror(errno));
  }

  // The reaper: stops the cluster and removes the folder when our end of the pipe closes.
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0) return make_error(503, std::string("pipe: ") + std::strerror(errno));
  const std::string pg_ctl = c->bin_ + "/pg_ctl";
  const std::string data = c->folder_ + "/data";
  const pid_t reaper = ::fork();
  if (reaper < 0) return make_error(503, std::string("fork: ") + std::strerror(errno));
  if (reaper == 0) {
    ::setsid();
    const int null_fd = ::open("/dev/null", O_RDWR);
    for (int fd = 0; fd < 3; ++fd) ::dup2(null_fd, fd);
    // Keep only the read end of the pipe.
    for (int fd = 3; fd < 1024; ++fd) {
      if (fd != fds[0]) ::close(fd);
    }
    for (;;) {
      char b;
      const ssize_t n = ::read(fds[0], &b, 1);
      if (n == 0 || (n < 0 && errno != EINTR)) break;
    }
    const pid_t stopper = ::fork();
    if (stopper == 0) {
      if (c->as_postgres_) {
        ::setgid(c->gid_);
        ::setuid(c->uid_);
      }
      ::execl(pg_ctl.c_str(), pg_ctl.c_str(), "stop", "-D", data.c_str(), "-m", "immediate", "-w", static_cast<char*>(nullptr));
      ::_exit(127);
    }
    int status = 0;
    if (stopper > 0) ::waitpid(stopper, &status, 0);
    std::error_code ec;
    fs::remove_all(c->folder_, ec);
    ::_exit(0);
  }
  ::close(fds[0]);
  c->reaper_ = reaper;
  c->reaper_pipe_ = fds[1];

  if (c->pg({c->bin_ + "/initdb", "-D", data, "-U", "cathbox", "--auth=trust", "-E", "UTF8", "--no-locale", "--no-sync"}) != 0) {
    return make_error(503, "postgresql: initdb failed: " + c->log_tail());
  }
  // Settings for a private test server: socket in our folder only, small shared memory.
  {
    std::ofstream conf(data + "/postgresql.conf", std::ios::app);
    conf << "listen_addresses = ''\n"
         << "unix_socket_directories = '" << c->folder_ << "'\n"
         << "max_connections = " << options.max_connections << "\n"
         << "shared_buffers = 32MB\n"
         << "fsync = " << (options.fsync ? "on" : "off") << "\n"
         << "full_page_writes = " << (options.fsync ? "on" : "off") << "\n"
         << "log_min_messages = warning\n";
  }
  if (Status s = c->start_again(); !s) return s.error();
  // The database the URLs name by default.
  if (Status s = c->create_database("cathbox"); !s) return s.error();
  return c;
}

PgCluster::~PgCluster() {
  if (running_) (void)stop("fast");
  if (reaper_pipe_ >= 0) ::close(reaper_pipe_);  // the reaper removes the folder
  if (reaper_ > 0) {
    int status = 0;
    while (::waitpid(reaper_, &status, 0) < 0 && errno == EINTR) {
    }
  }
}

std::string PgCluster::url(const std::string& database) const {
  return "postgresql:///" + database + "?host=" + folder_ + "&user=cathbox";
}

Status PgCluster::create_database(const std::string& name) {
  const int rc = pg({bin_ + "/createdb", "-h", folder_, "-U", "cathbox", name});
  if (rc != 0) return make_error(503, "postgresql: createdb " + name + " failed: " + log_tail());
  return Ok{};
}

Status PgCluster::stop(const std::string& mode) {
  const int rc = pg({bin_ + "/pg_ctl", "stop", "-D", folder_ + "/data", "-m", mode, "-w"});
  running_ = false;
  if (rc != 0) return make_error(503, "postgresql: pg_ctl stop failed: " + log_tail());
  return Ok{};
}

Status PgCluster::start_again() {
  const int rc = pg({bin_ + "/pg_ctl", "start", "-D", folder_ + "/data", "-l", folder_ + "/server.log", "-w", "-t", "60"});
  if (rc != 0) return make_error(503, "postgresql: pg_ctl start failed: " + log_tail());
  running_ = true;
  return Ok{};
}

std::string PgCluster::log_tail(std::size_t bytes) const {
  std::string all;
  for (const char* name : {"/tools.log", "/server.log"}) {
    std::ifstream in(folder_ + name, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    all += ss.str();
  }
  if (all.size() > bytes) all = all.substr(all.size() - bytes);
  std::replace(all.begin(), all.end(), '\n', ' ');
  return all;
}

}  // namespace cathbox::server::testing
