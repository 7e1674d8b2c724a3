#include "app/server_link.hpp"

#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <filesystem>
#include <fstream>
#include <mutex>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "server/client.hpp"
#include "server/client_queue.hpp"
#include "server/json_input.hpp"
#include "server/tls.hpp"
#include "session/records_dir.hpp"

namespace cathbox::app {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr std::int64_t kFramePeriod_us = 1'000'000 / 30;

std::string host_name() {
  char buf[256] = {};
  if (::gethostname(buf, sizeof buf - 1) != 0) buf[0] = '\0';
  return server::to_slug(buf, "rig");
}

// The assignment list this rig last saw, so a run started offline still counts for its
// assignment when its record is uploaded later.
std::string assignments_cache(const ServerLinkOptions& o) { return o.cache_dir + "/assignments-" + o.user + ".json"; }

void save_assigned(const ServerLinkOptions& o, const std::vector<AssignedCase>& list) {
  json out = json::array();
  for (const AssignedCase& a : list) {
    out.push_back({{"id", a.info.id}, {"case", a.info.case_name}, {"version", a.info.case_version}, {"note", a.info.note},
                   {"criteria", a.info.criteria_json}, {"due_at", a.info.due_at}, {"path", a.case_path}});
  }
  (void)server::write_file_durably(assignments_cache(o), out.dump(1));
}

std::vector<AssignedCase> load_assigned(const ServerLinkOptions& o) {
  std::vector<AssignedCase> list;
  std::ifstream in(assignments_cache(o));
  if (!in) return list;
  try {
    for (const json& a : json::parse(in)) {
      AssignedCase c;
      c.info.id = a.at("id").get<std::int64_t>();
      c.info.case_name = a.at("case").get<std::string>();
      c.info.case_version = a.at("version").get<int>();
      c.info.note = a.at("note").get<std::string>();
      c.info.criteria_json = a.at("criteria").get<std::string>();
      c.info.due_at = a.at("due_at").get<std::string>();
      c.case_path = a.at("path").get<std::string>();
      std::error_code ec;
      if (!c.case_path.empty() && fs::exists(c.case_path, ec)) list.push_back(std::move(c));
    }
  } catch (const std::exception&) {
    list.clear();  // a damaged cache is only a cache: the next online start rewrites it
  }
  return list;
}

}  // namespace

struct ServerLink::Impl {
  explicit Impl(const ServerLinkOptions& o) : client(o.url, o.timeout_ms), queue(o.queue_dir) {}

  std::mutex client_mutex;  // the client and the queue: the worker and flush_now()
  server::ServerClient client;
  server::UploadQueue queue;
  std::atomic<bool> online{false};
  std::string password;
  std::string user;

  std::unique_ptr<server::LiveStream> stream;
  std::vector<std::string> tool_names;
  std::int64_t last_frame_us = -1;
  std::uint64_t seq = 0;

  std::mutex worker_mutex;
  std::condition_variable worker_wake;
  bool flush_wanted = false;
  bool stopping = false;
  server::FlushReport last;
  std::thread worker;

  // Caller holds client_mutex.
  bool log_in(std::string* why) {
    const server::Status s = client.login(user, password);
    online = s.ok();
    if (!s && why != nullptr) *why = s.error().message;
    return s.ok();
  }

  server::FlushReport flush() {
    std::lock_guard lock(client_mutex);
    std::string why;
    if (client.token().empty() && !log_in(&why)) {
      server::FlushReport out;
      out.left = static_cast<int>(queue.pending().size());
      out.stopped_by = why;
      return out;
    }
    server::FlushReport r = queue.flush(client);
    if (r.left > 0 && !r.stopped_by.empty() && log_in(&why)) {
      // The token may have expired (401): once more with a fresh one.
      const server::FlushReport again = queue.flush(client);
      r.stored += again.stored;
      r.duplicates += again.duplicates;
      r.refused += again.refused;
      r.left = again.left;
      r.stopped_by = again.stopped_by;
    }
    online = r.stopped_by.empty() || !r.stopped_by.starts_with("connect");
    return r;
  }

  void run_worker() {
    for (;;) {
      {
        std::unique_lock lock(worker_mutex);
        worker_wake.wait(lock, [&] { return stopping || flush_wanted; });
        if (!flush_wanted) return;
        flush_wanted = false;
      }
      const server::FlushReport s = flush();
      std::lock_guard lock(worker_mutex);
      last = s;
    }
  }
};

ServerLink::ServerLink(ServerLinkOptions options) : options_(std::move(options)), impl_(std::make_unique<Impl>(options_)) {}

std::unique_ptr<ServerLink> ServerLink::open(const ServerLinkOptions& options, std::string& note) {
  ServerLinkOptions o = options;
  if (o.rig.empty()) o.rig = host_name();
  if (o.cache_dir.empty()) o.cache_dir = default_server_cache_dir();
  if (o.queue_dir.empty()) o.queue_dir = session::user_dir(session::UserDir::kData, "upload-queue");
  server::set_client_ca_file(o.ca_file);  // every client of this process: the link's and its live stream's
  std::unique_ptr<ServerLink> link(new ServerLink(o));
  Impl& im = *link->impl_;
  im.user = o.user;
  im.password = o.password;
  std::string why;
  std::vector<AssignedCase> list;
  bool fetched = false;
  {
    std::lock_guard lock(im.client_mutex);
    if (im.log_in(&why)) {
      server::Result<std::vector<server::AssignmentInfo>> got = im.client.assignments();
      if (got) {
        fetched = true;
        for (const server::AssignmentInfo& a : got.value()) {
          AssignedCase c;
          c.info = a;
          server::Result<std::string> path = im.client.download_case(a.case_name, a.case_version, o.cache_dir + "/cases");
          if (path) {
            c.case_path = path.value();
          } else {
            note += (note.empty() ? "" : "; ") + ("case " + a.case_name + ": " + path.error().message);
          }
          list.push_back(std::move(c));
        }
      } else {
        why = got.error().message;
      }
    }
  }
  if (fetched) {
    save_assigned(o, list);
    std::erase_if(list, [](const AssignedCase& c) { return c.case_path.empty(); });
    link->assigned_ = std::move(list);
  } else {
    link->assigned_ = load_assigned(o);
    note += (note.empty() ? "" : "; ") + ("server " + o.url + " unreachable (" + why + "): working offline, records queue in " +
                                          o.queue_dir);
  }
  im.worker = std::thread([&im] { im.run_worker(); });
  return link;
}

ServerLink::~ServerLink() {
  impl_->stream.reset();
  {
    std::lock_guard lock(impl_->worker_mutex);
    impl_->stopping = true;
  }
  impl_->worker_wake.notify_all();
  if (impl_->worker.joinable()) impl_->worker.join();
}

bool ServerLink::online() const { return impl_->online.load(); }

std::optional<std::int64_t> ServerLink::assignment_for(const std::string& case_path) const {
  std::error_code ec;
  for (const AssignedCase& a : assigned_) {
    if (a.case_path == case_path || fs::equivalent(a.case_path, case_path, ec)) return a.info.id;
  }
  return std::nullopt;
}

void ServerLink::begin_run(const std::string& case_name, std::optional<std::int64_t> assignment_id,
                           std::vector<std::string> tool_names) {
  impl_->stream.reset();
  impl_->tool_names = std::move(tool_names);
  impl_->last_frame_us = -1;
  impl_->seq = 0;
  std::string token;
  {
    std::lock_guard lock(impl_->client_mutex);
    if (impl_->client.token().empty() && !impl_->log_in(nullptr)) return;  // offline: no stream
    token = impl_->client.token();
  }
  server::LiveStream::Options s;
  s.base_url = options_.url;
  s.token = token;
  s.rig = options_.rig;
  // The server names cases by slug; a local case file's name is made into one.
  s.case_name = server::to_slug(case_name, "case");
  for (const AssignedCase& a : assigned_) {
    if (assignment_id && a.info.id == *assignment_id) {
      s.case_name = a.info.case_name;  // the server's name for it
      s.case_version = a.info.case_version;
    }
  }
  s.assignment_id = assignment_id;
  impl_->stream = std::make_unique<server::LiveStream>(std::move(s));
}

bool ServerLink::wait_streaming(int timeout_ms) {
  if (!impl_->stream) return false;
  const auto until = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
  while (!impl_->stream->connected()) {
    if (std::chrono::steady_clock::now() >= until) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

void ServerLink::publish(const session::SceneSnapshot& snap) {
  if (!impl_->stream) return;
  if (impl_->last_frame_us >= 0 && snap.sim_time_us - impl_->last_frame_us < kFramePeriod_us && !snap.run_over) return;
  impl_->last_frame_us = snap.sim_time_us;
  impl_->stream->push(frame_json(snap, ++impl_->seq, impl_->tool_names));
}

std::string ServerLink::end_run(const std::string& record_path, std::optional<std::int64_t> assignment_id, bool background) {
  impl_->stream.reset();  // sends {"type": "end"}
  if (record_path.empty()) return {};
  {
    std::lock_guard lock(impl_->client_mutex);
    server::Result<std::string> queued = impl_->queue.enqueue_file(record_path, assignment_id);
    if (!queued) return "cannot queue the record for the server: " + queued.error().message;
  }
  if (!background) return {};
  {
    std::lock_guard lock(impl_->worker_mutex);
    impl_->flush_wanted = true;
  }
  impl_->worker_wake.notify_one();
  return {};
}

server::FlushReport ServerLink::flush_now() {
  server::FlushReport s = impl_->flush();
  std::lock_guard lock(impl_->worker_mutex);
  impl_->last = s;
  return s;
}

std::string ServerLink::status_line() const {
  std::size_t queued = 0;
  {
    std::lock_guard lock(impl_->client_mutex);
    queued = impl_->queue.pending().size();
  }
  std::ostringstream out;
  out << "server " << options_.url << ": " << (online() ? "online as " + options_.user : std::string("offline")) << ", rig "
      << options_.rig << ", " << assigned_.size() << " assignment" << (assigned_.size() == 1 ? "" : "s") << ", " << queued
      << " record" << (queued == 1 ? "" : "s") << " queued";
  return out.str();
}

std::string default_server_cache_dir() { return session::user_dir(session::UserDir::kCache, "server"); }

}  // namespace cathbox::app
