#include "server/server_metrics.hpp"

#include <charconv>
#include <set>

namespace cathbox::server {

namespace {

// Path segments kept as they are in a route; any other segment is an id or a name.
const std::set<std::string_view> kWords = {"api",   "v1",     "me",     "login",  "logout",  "password", "users",   "cases",
                                           "versions", "latest", "bundle", "mesh", "assignments", "results", "record", "trace",
                                           "metrics", "live",   "rigs",   "stream", "watch",   "debrief",  "audit",   "healthz",
                                           "readyz"};

// The shortest text that reads back as the same double ("0.0025", not "0.0025000000000000001").
std::string number(double v) {
  char text[64];
  const auto end = std::to_chars(text, text + sizeof text, v).ptr;
  return std::string(text, end);
}

}  // namespace

void ServerMetrics::Histogram::add(double seconds) {
  for (std::size_t i = 0; i < kBuckets_s.size(); ++i) {
    if (seconds <= kBuckets_s[i]) ++below[i];
  }
  ++count;
  sum_s += seconds;
}

void ServerMetrics::observe_request(const std::string& route, int status, double seconds) {
  std::lock_guard lock(mutex_);
  ++requests_[{route, status}];
  latency_[route].add(seconds);
}

void ServerMetrics::observe_upload_check(double seconds) {
  std::lock_guard lock(mutex_);
  upload_check_.add(seconds);
}

std::string ServerMetrics::route_of(std::string_view method, std::string_view target) {
  const std::string_view path = target.substr(0, target.find('?'));
  // Any other method is one label: a client inventing methods cannot grow the label set.
  static const std::set<std::string_view> kMethods = {"GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS"};
  std::string route(kMethods.count(method) != 0 ? method : std::string_view("OTHER"));
  route += ' ';
  if (path.rfind("/api/", 0) != 0 && path != "/healthz" && path != "/readyz" && path != "/metrics") return route + "static";
  for (std::size_t at = 1; at <= path.size();) {
    const std::size_t slash = std::min(path.find('/', at), path.size());
    const std::string_view seg = path.substr(at, slash - at);
    route += '/';
    route += kWords.count(seg) != 0 ? std::string(seg) : std::string(":id");
    at = slash + 1;
  }
  return route;
}

std::string ServerMetrics::render(const ScrapeGauges& g) const {
  std::string out;
  const auto hist = [&out](const char* name, const std::string& labels, const Histogram& h) {
    for (std::size_t i = 0; i < kBuckets_s.size(); ++i) {
      out += std::string(name) + "_bucket{" + labels + (labels.empty() ? "" : ",") + "le=\"" + number(kBuckets_s[i]) + "\"} " +
             std::to_string(h.below[i]) + "\n";
    }
    out += std::string(name) + "_bucket{" + labels + (labels.empty() ? "" : ",") + "le=\"+Inf\"} " + std::to_string(h.count) + "\n";
    const std::string braces = labels.empty() ? "" : "{" + labels + "}";
    out += std::string(name) + "_sum" + braces + " " + number(h.sum_s) + "\n";
    out += std::string(name) + "_count" + braces + " " + std::to_string(h.count) + "\n";
  };
  {
    std::lock_guard lock(mutex_);
    out += "# HELP cathbox_http_requests_total HTTP requests answered, by route and status.\n";
    out += "# TYPE cathbox_http_requests_total counter\n";
    for (const auto& [key, n] : requests_) {
      out += "cathbox_http_requests_total{route=\"" + key.first + "\",status=\"" + std::to_string(key.second) + "\"} " +
             std::to_string(n) + "\n";
    }
    out += "# HELP cathbox_http_request_seconds Time from a request's last byte read to its answer's last byte written.\n";
    out += "# TYPE cathbox_http_request_seconds histogram\n";
    for (const auto& [route, h] : latency_) hist("cathbox_http_request_seconds", "route=\"" + route + "\"", h);
    out += "# HELP cathbox_upload_check_seconds Checking an uploaded record (replay) or case (meshing).\n";
    out += "# TYPE cathbox_upload_check_seconds histogram\n";
    hist("cathbox_upload_check_seconds", "", upload_check_);
  }
  const auto gauge = [&out](const char* name, const char* help, double v) {
    out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " gauge\n" + name + " " + number(v) + "\n";
  };
  const auto counter = [&out](const char* name, const char* help, double v) {
    out += std::string("# HELP ") + name + " " + help + "\n# TYPE " + name + " counter\n" + name + " " + number(v) + "\n";
  };
  gauge("cathbox_open_connections", "TCP connections open (HTTP and WebSocket).", static_cast<double>(g.open_connections));
  gauge("cathbox_live_rigs", "Rigs streaming a live session to this instance.", static_cast<double>(g.live_publishers));
  gauge("cathbox_live_watchers", "Live watcher sockets open on this instance.", static_cast<double>(g.live_watchers));
  gauge("cathbox_upload_queue", "Uploads being checked or waiting for a check.", g.heavy_queued);
  gauge("cathbox_db_pool_open", "Database connections open.", g.pool.open);
  gauge("cathbox_db_pool_idle", "Database connections idle.", g.pool.idle);
  gauge("cathbox_db_pool_max", "Database connections allowed.", g.pool.max);
  gauge("cathbox_db_pool_waiting", "Callers waiting for a database connection.", g.pool.waiting);
  counter("cathbox_live_frames_in_total", "Live frames received from rigs.", static_cast<double>(g.frames_in));
  counter("cathbox_live_frames_out_total", "Live frames sent to watchers.", static_cast<double>(g.frames_out));
  counter("cathbox_live_frames_dropped_total", "Live frames dropped for slow watchers.", static_cast<double>(g.frames_dropped));
  return out;
}

}  // namespace cathbox::server
