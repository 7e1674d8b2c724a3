#pragma once
// The server's operational metrics, served at /metrics in the Prometheus text exposition format
// (version 0.0.4): requests by route and status, request latency and upload-check histograms,
// and gauges read at scrape time (connections, live rigs and watchers, the upload queue, the
// database pool, live frames).
//
// Routes are the API's patterns, not raw paths ("GET /api/v1/results/:id"), so the label set
// stays small whatever clients send; static files are "GET static".
#include <array>
#include <cstdint>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>

#include "server/sql.hpp"

namespace cathbox::server {

struct ScrapeGauges {
  std::size_t open_connections = 0;
  std::uint64_t live_publishers = 0;  // rigs streaming now
  std::uint64_t live_watchers = 0;    // watcher sockets open now
  int heavy_queued = 0;               // uploads waiting for or in a check (meshing, replay)
  PoolStats pool;
  std::uint64_t frames_in = 0, frames_out = 0, frames_dropped = 0;
};

class ServerMetrics {
 public:
  static constexpr std::array<double, 14> kBuckets_s = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05,
                                                        0.1,    0.25,  0.5,    1.0,   2.5,  5.0,   10.0};

  void observe_request(const std::string& route, int status, double seconds);
  // A record or case upload's check (replay, meshing) on the heavy threads.
  void observe_upload_check(double seconds);
  [[nodiscard]] std::string render(const ScrapeGauges& gauges) const;

  // "GET /api/v1/results/:id" from a method and a request target.
  [[nodiscard]] static std::string route_of(std::string_view method, std::string_view target);

 private:
  struct Histogram {
    std::array<std::uint64_t, kBuckets_s.size()> below{};  // cumulative at render time
    std::uint64_t count = 0;
    double sum_s = 0.0;
    void add(double seconds);
  };
  mutable std::mutex mutex_;
  std::map<std::pair<std::string, int>, std::uint64_t> requests_;
  std::map<std::string, Histogram> latency_;
  Histogram upload_check_;
};

}  // namespace cathbox::server
