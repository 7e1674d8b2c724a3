// `cathbox selftest`: runs the box's self-test (encoders, actuators, E-stop loop, calibration)
// and prints the result. Exit 0 when it passed, 1 when it failed.
#include <cstdio>

#include "box_session.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"

namespace cathbox::cli {
namespace {

std::string failed_names(uint16_t checks) {
  static const char* const table[] = {"insertion-encoder", "rotation-encoder", "insertion-actuator",
                                      "rotation-actuator", "estop-loop",       "calibration"};
  std::string out;
  for (int i = 0; i < 6; ++i) {
    if (checks & (1u << i)) out += (out.empty() ? "" : ",") + std::string(table[i]);
  }
  return out.empty() ? "-" : out;
}

int run_selftest(std::span<const std::string> argv) {
  Args args(argv, {"emu", "timeout"}, {"json"});
  const auto timeout_s = args.number("timeout");
  if (!args.ok()) return fail_usage("selftest", args.error());
  if (!args.positionals().empty()) return fail_usage("selftest", "takes no arguments");
  if (timeout_s && (*timeout_s <= 0 || *timeout_s > kMaxSeconds)) {
    return fail_usage("selftest", "--timeout must be in (0, " + std::to_string(static_cast<int>(kMaxSeconds)) + "] s");
  }
  int code = 0;
  auto session = open_box("selftest", args, code);
  if (!session) return code;
  auto& box = *session->client;
  if (auto started = box.start_selftest(); !started) return fail("selftest", started.error());
  const bool json = args.flag("json");
  if (!json) std::printf("self-test running (keep hands off the tool)...\n");
  const std::int64_t deadline = session->clock.now_us() + static_cast<std::int64_t>(timeout_s.value_or(10.0) * 1e6);
  // The box starts the test at its next control tick and flags it in every state report while
  // it runs: wait for the flag to appear and to clear, then read the result (a read right after
  // the start could still return the previous run's result).
  device::BoxState state;
  bool seen_running = false;
  for (;;) {
    if (box.poll(state)) {
      const bool running = (state.report.status & CBX_STATUS_SELFTEST_RUNNING) != 0;
      if (running) seen_running = true;
      if (seen_running && !running) break;
    }
    if (box.link() == device::Link::kDown || session->clock.now_us() > deadline) {
      std::fprintf(stderr, "cathbox selftest: %s\n", seen_running ? "still running after the timeout" : "the box never started the test");
      return kExitDeviceError;
    }
    session->clock.wait(-1, 1000);
  }
  auto got = box.selftest();
  if (!got) return fail("selftest", got.error());
  const cbx_selftest result = got.value();
  const bool passed = result.state == CBX_SELFTEST_PASSED;
  if (json) {
    print_json(Json{{"result", passed ? "passed" : (result.state == CBX_SELFTEST_FAILED ? "failed" : "never-run")},
                    {"failed_checks", failed_names(result.failed_checks)},
                    {"insertion_current_mA", int64_t{result.insertion_current_mA}},
                    {"rotation_current_mA", int64_t{result.rotation_current_mA}},
                    {"supply_mV", unsigned{result.supply_mV}}});
  } else {
    std::printf("self-test %s\n", passed ? "PASSED" : "FAILED");
    if (!passed) std::printf("failed checks   %s\n", failed_names(result.failed_checks).c_str());
    std::printf("test currents   insertion %d mA, rotation %d mA\nsupply          %u mV\n", result.insertion_current_mA,
                result.rotation_current_mA, result.supply_mV);
  }
  return passed ? kExitOk : kExitFailure;
}

const Registrar registrar({"selftest", "run the box's self-test [--emu PATH] [--json] [--timeout S]", run_selftest});

}  // namespace
}  // namespace cathbox::cli
