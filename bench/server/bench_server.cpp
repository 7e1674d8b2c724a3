// bench_server: the training centre under load, SQLite and PostgreSQL side by side, and the
// case library's bytes on the wire beside the thesis's Table 1.
//
//  - CaseSizes/<case>: each bundled case as the server stores and sends it (zstd level 19 of
//    the case + HCLM text) against the level-2 mesh the trainer builds from it; the thesis's
//    Table 1 (its model files before/after compression, 7-15x) is printed beside.
//  - Centre/<store>: 50 rigs streaming at 30 Hz to cathbox-server on loopback, 10 instructors
//    each watching 10 rigs and calling the API 5 times a second, 4 session records uploaded a
//    second by trainees (each replayed by the server before it is stored); warm-up 3 s, then
//    20 s measured (CATHBOX_BENCH_SECONDS). API p50/p99, stream delivery p50/p99 (push
//    on the rig to arrival at the watcher), uploads acknowledged vs found afterwards, the
//    server's resident memory after warm-up, at its peak and at the end.
//    "postgresql-2" runs the rigs on instance A and the instructors on instance B.
//    "sqlite-tls" is "sqlite" over HTTPS and wss:// (a throwaway CA made with the openssl
//    command, trusted through set_client_ca_file), to read the cost of TLS beside plain HTTP.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>

#include <benchmark/benchmark.h>

#include "centre_load.hpp"
#include "server/case_bundle.hpp"
#include "server/case_library.hpp"
#include "server/testing/pg_cluster.hpp"
#include "server/testing/test_ca.hpp"
#include "server/tls.hpp"
#include "server/zstd_codec.hpp"
#include "scenario/case_file.hpp"

namespace {

using namespace cathbox::server;

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

struct SizeRow {
  std::int64_t raw = 0, wire = 0, mesh = 0, triangles = 0;
};
std::map<std::string, SizeRow> g_sizes;
std::map<std::string, bench::LoadFigures> g_loads;

void CaseSizes(benchmark::State& state, const std::string& stem) {
  CaseBundle b;
  b.case_file = stem + ".case";
  b.case_text = read_text(std::string(CATHBOX_SOURCE_DIR) + "/cases/" + b.case_file);
  const cathbox::tool::CaseParse parsed = cathbox::tool::parse_case(b.case_text, b.case_file);
  if (parsed && !parsed->vessel_path.empty()) {
    b.hclm_file = parsed->vessel_path;
    b.hclm_text = read_text(std::string(CATHBOX_SOURCE_DIR) + "/cases/" + b.hclm_file);
  }
  const Result<CaseCheck> check = check_case(b);
  if (!check) {
    state.SkipWithError(check.error().message.c_str());
    return;
  }
  const std::string json = bundle_json(b);
  std::string wire;
  for (auto _ : state) {
    wire = zstd_compress(json, 19);
    benchmark::DoNotOptimize(wire.data());
  }
  SizeRow row{static_cast<std::int64_t>(b.case_text.size() + b.hclm_text.size()), static_cast<std::int64_t>(wire.size()),
              check.value().mesh_bytes, check.value().mesh_triangles};
  g_sizes[stem] = row;
  state.counters["raw_B"] = static_cast<double>(row.raw);
  state.counters["wire_B"] = static_cast<double>(row.wire);
  state.counters["mesh_B"] = static_cast<double>(row.mesh);
  state.counters["mesh/wire"] = static_cast<double>(row.mesh) / static_cast<double>(row.wire);
  state.counters["raw/wire"] = static_cast<double>(row.raw) / static_cast<double>(row.wire);
}

testing::PgCluster& cluster() {
  static std::unique_ptr<testing::PgCluster> c = [] {
    testing::PgClusterOptions o;
    o.fsync = true;  // durable commits, as SQLite's synchronous=FULL
    o.max_connections = 200;
    auto started = testing::PgCluster::start(o);
    if (!started) {
      std::fprintf(stderr, "%s\n", started.error().message.c_str());
      std::exit(1);
    }
    return std::move(started.value());
  }();
  return *c;
}

std::string temp_dir() {
  char templ[] = "/tmp/cathbox-bench-XXXXXX";
  return ::mkdtemp(templ);
}

void Centre(benchmark::State& state, const std::string& store) {
  bench::LoadOptions o;
  if (const char* s = std::getenv("CATHBOX_BENCH_SECONDS")) o.measure_s = std::max(2, std::atoi(s));
  std::string url, folder;
  if (store == "sqlite-tls") {
    folder = temp_dir();
    url = "sqlite:" + folder + "/centre.db";
    const testing::TestCa ca(folder, "bench-ca");
    const TlsFiles files = ca.issue("server", "IP:127.0.0.1");
    o.server_args = {"--tls-cert", files.cert_file, "--tls-key", files.key_file};
    set_client_ca_file(ca.ca_file());
  } else if (store == "sqlite") {
    folder = temp_dir();
    url = "sqlite:" + folder + "/centre.db";
  } else {
    static int n = 0;
    const std::string name = "centre" + std::to_string(++n);
    if (!cluster().create_database(name)) {
      state.SkipWithError("createdb failed");
      return;
    }
    url = cluster().url(name);
  }
  bench::LoadFigures f;
  for (auto _ : state) {
    try {
      f = bench::run_centre_load(url, store == "postgresql-2", o);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      return;
    }
  }
  if (!folder.empty()) std::filesystem::remove_all(folder);
  g_loads[store] = f;
  state.counters["api_p50_ms"] = bench::percentile(f.api_ms, 50);
  state.counters["api_p99_ms"] = bench::percentile(f.api_ms, 99);
  state.counters["stream_p50_ms"] = bench::percentile(f.stream_ms, 50);
  state.counters["stream_p99_ms"] = bench::percentile(f.stream_ms, 99);
  state.counters["frames_out/s"] = static_cast<double>(f.frames_delivered) / o.measure_s;
  state.counters["uploads_lost"] = static_cast<double>(f.uploads_acknowledged - f.uploads_verified);
  state.counters["rss_peak_MB"] = static_cast<double>(f.rss_peak_kb) / 1024.0;
}

void print_summary() {
  std::printf("\nCase bundles on the wire vs the level-2 mesh the trainer builds (zstd -19 of case + HCLM text;\n"
              "mesh = 24 B/vertex + 12 B/triangle)\n");
  std::printf("%-18s %10s %10s %12s %10s %9s %9s\n", "case", "raw B", "wire B", "mesh B", "triangles", "raw/wire", "mesh/wire");
  for (const auto& [name, r] : g_sizes) {
    std::printf("%-18s %10lld %10lld %12lld %10lld %8.1fx %8.1fx\n", name.c_str(), static_cast<long long>(r.raw), static_cast<long long>(r.wire),
                static_cast<long long>(r.mesh), static_cast<long long>(r.triangles), static_cast<double>(r.raw) / static_cast<double>(r.wire),
                static_cast<double>(r.mesh) / static_cast<double>(r.wire));
  }
  std::printf("thesis Table 1 (model file before -> after compression): aneurysm 362->50 KB 7.2x, abdomen 257->41 KB 6.3x,\n"
              "  heart 30->4 KB 7.5x, phantom 151->20 KB 7.6x, human body 2 MB->135 KB 15.2x\n");
  if (g_loads.empty()) return;
  std::printf("\nCentre load: 50 rigs x 30 Hz, 10 instructors x 10 rigs watched + 5 API calls/s, 4 record uploads/s\n");
  std::printf("%-14s %9s %9s %11s %11s %10s %10s %9s %8s %9s %9s %9s\n", "store", "api p50", "api p99", "stream p50", "stream p99",
              "frames in", "frames out", "uploads", "lost", "RSS warm", "RSS peak", "RSS end");
  for (const auto& [name, f] : g_loads) {
    std::printf("%-14s %7.2fms %7.2fms %9.2fms %9.2fms %10lld %10lld %9lld %8lld %7.0fMB %7.0fMB %7.0fMB\n", name.c_str(),
                bench::percentile(f.api_ms, 50), bench::percentile(f.api_ms, 99), bench::percentile(f.stream_ms, 50),
                bench::percentile(f.stream_ms, 99), static_cast<long long>(f.frames_pushed), static_cast<long long>(f.frames_delivered),
                static_cast<long long>(f.uploads_acknowledged), static_cast<long long>(f.uploads_acknowledged - f.uploads_verified),
                static_cast<double>(f.rss_after_warmup_kb) / 1024.0, static_cast<double>(f.rss_peak_kb) / 1024.0,
                static_cast<double>(f.rss_end_kb) / 1024.0);
  }
  std::printf("(frame %lld bytes; API errors: ", static_cast<long long>(g_loads.begin()->second.frame_bytes));
  for (const auto& [name, f] : g_loads) std::printf("%s %lld ", name.c_str(), static_cast<long long>(f.api_errors));
  std::printf(")\n");
}

}  // namespace

int main(int argc, char** argv) {
  for (const char* stem : {"y_bifurcation", "neuro", "neuro_aneurysm", "neuro_stenosis"}) {
    benchmark::RegisterBenchmark(("CaseSizes/" + std::string(stem)).c_str(), CaseSizes, std::string(stem))->Unit(benchmark::kMillisecond);
  }
  for (const char* store : {"sqlite", "sqlite-tls", "postgresql", "postgresql-2"}) {
    benchmark::RegisterBenchmark(("Centre/" + std::string(store)).c_str(), Centre, std::string(store))
        ->Iterations(1)
        ->UseRealTime()
        ->Unit(benchmark::kSecond);
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  print_summary();
  return 0;
}
