// cathbox-emu: the emulated box, served in real time on a Unix-domain socket.
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "emu/emulator.hpp"
#include "emu/real_time_loop.hpp"
#include "protocol/cbx_emu_frame.h"

namespace {

std::atomic<bool> stop_requested{false};  // lock-free: safe to set from a signal handler
void on_signal(int) { stop_requested.store(true); }

void usage() {
  std::printf(
      "usage: cathbox-emu [OPTIONS]\n"
      "Runs the emulated Cathbox (firmware core on a simulated board) in real time and serves it\n"
      "on a Unix-domain socket, as `cathbox --emu PATH` and the trainer expect.\n\n"
      "  --socket PATH          socket path (default $CATHBOX_EMU_SOCKET, $XDG_RUNTIME_DIR/cathbox-emu.sock,\n"
      "                         or /tmp/cathbox-emu.sock)\n"
      "  --motor                DC motors on both axes (default: magnetic-particle brakes)\n"
      "  --uncalibrated         start with an empty settings store\n"
      "  --serial TEXT          serial number reported in device info (default EMU-0001)\n"
      "  --hand-insertion S     scripted hand on the insertion axis, e.g. v:0.02:2s,f:-1.5:500ms,free:1s\n"
      "  --hand-rotation S      same for rotation (rad/s, N*m)\n"
      "  --drop P --duplicate P --corrupt P   fault probabilities for reports in both directions\n"
      "  --delay P:US           hold a report back US microseconds with probability P\n"
      "  --encoder-bounce P     encoder line chatter per transition\n"
      "  --estop-after MS       press the E-stop after MS milliseconds\n"
      "  --seed N               seed of the fault injection (default 1)\n"
      "  --wire-version N       send reports with protocol major N (tests the host's version check)\n"
      "  --duration S           exit after S seconds (default: run until SIGINT/SIGTERM)\n");
}

bool parse_probability(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0' && out >= 0 && out <= 1;
}

// A whole decimal number in [0, max]: no sign, no trailing characters, no overflow.
bool parse_count(const char* text, unsigned long long max, unsigned long long& out) {
  if (*text < '0' || *text > '9') return false;
  char* end = nullptr;
  errno = 0;
  out = std::strtoull(text, &end, 10);
  return *end == '\0' && errno == 0 && out <= max;
}

// Seconds in (0, one year].
bool parse_seconds(const char* text, double& out) {
  char* end = nullptr;
  out = std::strtod(text, &end);
  return end != text && *end == '\0' && std::isfinite(out) && out > 0 && out <= 365.0 * 86400.0;
}

uint64_t wall_us() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

}  // namespace

int main(int argc, char** argv) {
  using cathbox::emu::Emulator;
  cathbox::emu::EmuOptions options;
  std::string path;
  std::string hand[2];
  double drop = 0, duplicate = 0, corrupt = 0, delay_p = 0, bounce = 0;
  uint64_t delay_us = 0;
  long long estop_after_ms = -1;
  int wire_version = CBX_PROTOCOL_VERSION;
  double duration_s = 0;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    auto value = [&]() -> const char* { return argv[++i]; };
    bool ok = true;
    if (arg == "--help" || arg == "-h") {
      usage();
      return 0;
    } else if (arg == "--motor") {
      options.motor = true;
    } else if (arg == "--uncalibrated") {
      options.calibrated = false;
    } else if (!has_value) {
      ok = false;
    } else if (arg == "--socket") {
      path = value();
    } else if (arg == "--serial") {
      options.serial = value();
    } else if (arg == "--hand-insertion") {
      hand[0] = value();
    } else if (arg == "--hand-rotation") {
      hand[1] = value();
    } else if (arg == "--drop") {
      ok = parse_probability(value(), drop);
    } else if (arg == "--duplicate") {
      ok = parse_probability(value(), duplicate);
    } else if (arg == "--corrupt") {
      ok = parse_probability(value(), corrupt);
    } else if (arg == "--encoder-bounce") {
      ok = parse_probability(value(), bounce);
    } else if (arg == "--delay") {
      const std::string v = value();
      const size_t colon = v.find(':');
      unsigned long long us = 0;
      ok = colon != std::string::npos && parse_probability(v.substr(0, colon).c_str(), delay_p) &&
           parse_count(v.c_str() + colon + 1, 10'000'000ull, us);
      delay_us = us;
    } else if (arg == "--estop-after") {
      unsigned long long ms = 0;
      ok = parse_count(value(), 365ull * 86'400'000ull, ms);
      estop_after_ms = static_cast<long long>(ms);
    } else if (arg == "--wire-version") {
      unsigned long long version = 0;
      ok = parse_count(value(), 255, version);
      wire_version = static_cast<int>(version);
    } else if (arg == "--seed") {
      unsigned long long seed = 0;
      ok = parse_count(value(), UINT64_MAX, seed);
      options.seed = seed;
    } else if (arg == "--duration") {
      ok = parse_seconds(value(), duration_s);
    } else {
      ok = false;
    }
    if (!ok) {
      if (has_value && arg != argv[i]) {
        std::fprintf(stderr, "cathbox-emu: option %s: bad value '%s' (see --help)\n", arg.c_str(), argv[i]);
      } else {
        std::fprintf(stderr, "cathbox-emu: bad or incomplete option '%s' (see --help)\n", arg.c_str());
      }
      return 2;
    }
  }
  if (path.empty()) {
    char buffer[108];
    if (cbx_emu_default_socket_path(buffer, sizeof buffer) != CBX_OK) {
      std::fprintf(stderr, "cathbox-emu: default socket path too long; use --socket\n");
      return 2;
    }
    path = buffer;
  }

  Emulator emu(options);
  for (int a = 0; a < 2; ++a) {
    if (hand[a].empty()) continue;
    auto script = cathbox::emu::HandScript::parse(hand[a]);
    if (!script) {
      std::fprintf(stderr, "cathbox-emu: %s\n", script.error().message.c_str());
      return 2;
    }
    emu.set_hand(a, script.value());
  }
  for (auto* link : {&emu.faults().in, &emu.faults().out}) {
    link->drop = drop;
    link->duplicate = duplicate;
    link->corrupt = corrupt;
    link->delay = delay_p;
    link->delay_us = delay_us;
  }
  emu.faults().encoder.bounce = bounce;
  emu.set_wire_version(static_cast<uint8_t>(wire_version));
  if (auto listening = emu.listen(path); !listening) {
    std::fprintf(stderr, "cathbox-emu: %s\n", listening.error().message.c_str());
    return 3;
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  std::printf("cathbox-emu: listening on %s\n", path.c_str());
  std::fflush(stdout);

  const uint64_t start = wall_us();
  const uint64_t estop_at_us = estop_after_ms >= 0 ? static_cast<uint64_t>(estop_after_ms) * 1000u : UINT64_MAX;
  cathbox::emu::RealTimeLoop::run(emu, stop_requested, duration_s > 0 ? static_cast<uint64_t>(duration_s * 1e6) : 0,
                                  [&](uint64_t now_us) {
                                    if (now_us >= estop_at_us) emu.set_estop(true);
                                  });
  std::printf("cathbox-emu: stopped after %.1f s, %llu IN reports sent\n", (wall_us() - start) * 1e-6,
              static_cast<unsigned long long>(emu.in_reports_sent()));
  return 0;
}
