// bench_device: the host <-> box link in real time, against cathbox-emu's box running in a
// thread on the wall clock (RealTimeLoop) and reached over the emulator socket.
//  - RoundTrip: a command leaves BoxClient::send(); the time until a state report echoes its
//    sequence number (the box applies commands at its next 10 kHz tick and reports once per
//    1 ms USB frame, so the frame dominates). Median and p99 as counters.
//  - SustainedRate: state reports accepted per second while commands go out every poll.
//  - Peer: RawSeqpacketEcho, a bare SOCK_SEQPACKET ping-pong of 68-byte datagrams between two
//    threads, the floor of the socket transport itself.
#include <benchmark/benchmark.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <thread>
#include <vector>

#include "device/box_client.hpp"
#include "device/box_opener.hpp"
#include "device/clock.hpp"
#include "emu/emulator.hpp"
#include "emu/real_time_loop.hpp"
#include "../bench_samples.hpp"

namespace {

using cathbox::device::BoxClient;
using cathbox::device::BoxState;
using cathbox::device::SystemClock;

struct RunningEmulator {
  std::string path = "/tmp/cathbox-bench-" + std::to_string(::getpid()) + ".sock";
  cathbox::emu::Emulator emu;
  std::atomic<bool> stop{false};
  std::thread thread;
  RunningEmulator() {
    if (!emu.listen(path)) std::abort();
    thread = std::thread([this] { cathbox::emu::RealTimeLoop::run(emu, stop, 0); });
  }
  ~RunningEmulator() {
    stop = true;
    thread.join();
  }
};

cbx_command_report idle_command() {
  cbx_command_report c{};
  c.mode = CBX_MODE_BRAKE;
  c.insertion = {0, 0, 0, 0, 0, 0};
  c.rotation = {0, 0, 0, 0, 0, 0};
  return c;
}

std::unique_ptr<BoxClient> connect_or_skip(benchmark::State& bench, RunningEmulator& box, SystemClock& clock) {
  auto client = BoxClient::connect(cathbox::device::box_opener(box.path, clock), clock);
  if (!client) {
    bench.SkipWithError(client.error().message.c_str());
    return nullptr;
  }
  return std::move(client.value());
}

// What the emulator benchmarks start from: a running emulator, its clock, a connected client
// (null after SkipWithError), the idle command and a state to poll into.
struct Session {
  RunningEmulator box;
  SystemClock clock;
  std::unique_ptr<BoxClient> client;
  const cbx_command_report command = idle_command();
  BoxState state{};
  explicit Session(benchmark::State& bench) : client(connect_or_skip(bench, box, clock)) {}
};

double percentile(const std::vector<double>& v, double q) { return cathbox::bench::quantile(v, q); }

void RoundTrip(benchmark::State& bench) {
  Session s(bench);
  if (!s.client) return;
  auto& c = *s.client;
  std::vector<double> samples_us;
  for (auto _ : bench) {
    const uint16_t seq = c.next_command_seq();
    const uint64_t sent = s.clock.now_us();
    (void)c.send(s.command);
    for (;;) {
      if (c.poll(s.state) && static_cast<uint16_t>(s.state.report.command_seq_echo - seq) < 0x8000u) break;
      if (s.clock.now_us() - sent > 100'000) break;
      s.clock.wait(-1, 50);  // yield the core to the emulator thread (2-core machines)
    }
    samples_us.push_back(static_cast<double>(s.clock.now_us() - sent));
  }
  bench.counters["median_us"] = percentile(samples_us, 0.5);
  bench.counters["p99_us"] = percentile(samples_us, 0.99);
  bench.counters["rejected"] = static_cast<double>(c.stats().rejected());
}
BENCHMARK(RoundTrip)->Iterations(2000)->UseRealTime()->Unit(benchmark::kMicrosecond);

void SustainedRate(benchmark::State& bench) {
  Session s(bench);
  if (!s.client) return;
  auto& c = *s.client;
  double rate = 0;
  for (auto _ : bench) {
    const uint64_t start = s.clock.now_us();
    const uint64_t accepted0 = c.stats().states_accepted;
    const uint64_t missed0 = c.stats().states_missed;
    while (s.clock.now_us() - start < 2'000'000) {
      if (c.poll(s.state)) (void)c.send(s.command);
      s.clock.wait(-1, 200);
    }
    rate = static_cast<double>(c.stats().states_accepted - accepted0) / ((s.clock.now_us() - start) * 1e-6);
    bench.counters["missed"] = static_cast<double>(c.stats().states_missed - missed0);
  }
  bench.counters["reports_per_s"] = rate;
}
BENCHMARK(SustainedRate)->Iterations(1)->UseRealTime()->Unit(benchmark::kMillisecond);

void RawSeqpacketEcho(benchmark::State& bench) {
  int sv[2];
  if (::socketpair(AF_UNIX, SOCK_SEQPACKET, 0, sv) != 0) {
    bench.SkipWithError("socketpair");
    return;
  }
  std::thread echo([fd = sv[1]] {
    uint8_t buf[68];
    for (;;) {
      const ssize_t n = ::recv(fd, buf, sizeof buf, 0);
      if (n <= 0 || ::send(fd, buf, static_cast<size_t>(n), MSG_NOSIGNAL) != n) return;
    }
  });
  uint8_t buf[68] = {3};
  std::vector<double> samples_us;
  SystemClock clock;
  for (auto _ : bench) {
    const uint64_t t0 = clock.now_us();
    (void)::send(sv[0], buf, sizeof buf, MSG_NOSIGNAL);
    (void)::recv(sv[0], buf, sizeof buf, 0);
    samples_us.push_back(static_cast<double>(clock.now_us() - t0));
  }
  ::shutdown(sv[0], SHUT_RDWR);
  echo.join();
  ::close(sv[0]);
  ::close(sv[1]);
  bench.counters["median_us"] = percentile(samples_us, 0.5);
  bench.counters["p99_us"] = percentile(samples_us, 0.99);
}
BENCHMARK(RawSeqpacketEcho)->Iterations(20000)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
