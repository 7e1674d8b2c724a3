#pragma once
// The training-centre load for bench_server: 50 rigs streaming at 30 Hz, uploads from the rigs,
// 10 instructors watching and calling the API, against cathbox-server processes on loopback.
#include <cstdint>
#include <string>
#include <vector>

#include "../bench_samples.hpp"

namespace cathbox::server::bench {

using cathbox::bench::percentile;  // p in percent, interpolated

struct LoadOptions {
  int rigs = 50;
  int watchers = 10;
  int rigs_per_watcher = 10;   // each rig is watched by watchers * rigs_per_watcher / rigs instructors
  double frame_hz = 30.0;
  int tool_nodes = 64;         // per tool, two tools per frame
  double api_per_watcher_hz = 5.0;
  int uploaders = 4;
  double uploads_per_uploader_hz = 1.0;
  int warmup_s = 3;
  int measure_s = 20;
  std::vector<std::string> server_args;  // more cathbox-server options (--tls-cert/--tls-key: HTTPS and wss://)
};

struct LoadFigures {
  std::vector<double> api_ms;       // every API call's round trip in the measured window
  std::vector<double> stream_ms;    // push on the rig -> arrival at a watcher
  std::int64_t frames_pushed = 0;
  std::int64_t frames_delivered = 0;
  std::int64_t uploads_attempted = 0;
  std::int64_t uploads_acknowledged = 0;
  std::int64_t uploads_verified = 0;  // acknowledged and found in the database afterwards
  std::int64_t api_errors = 0;        // non-2xx answers
  std::int64_t rss_after_warmup_kb = 0;
  std::int64_t rss_end_kb = 0;
  std::int64_t rss_peak_kb = 0;
  std::int64_t frame_bytes = 0;
};

// Runs the load against fresh servers on `db_url`: one instance, or with `two_instances` the
// rigs stream to instance A while the instructors watch and call B (PostgreSQL only).
LoadFigures run_centre_load(const std::string& db_url, bool two_instances, const LoadOptions& options);


}  // namespace cathbox::server::bench
