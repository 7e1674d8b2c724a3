// `cathbox calibrate`: guided calibration of the encoders. The engineer moves the tool over a
// known travel (counts per mm) and turns it a known number of turns (counts per revolution);
// the result is written to the box (feature 0x11), which stores it. Full scale and output
// curves are kept unless given.
#include <cmath>
#include <cstdio>
#include <iostream>
#include <string>

#include "box_session.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"

namespace cathbox::cli {
namespace {

// Prints the guide's prompt on `guide` and waits for Enter; false when the input ended (aborts
// without writing anything).
bool wait_enter(std::FILE* guide, const char* prompt) {
  std::fprintf(guide, "%s [Enter] ", prompt);
  std::fflush(guide);
  std::string line;
  return static_cast<bool>(std::getline(std::cin, line));
}

// A state measured after the engineer pressed Enter: drops what queued up while waiting for
// the key, then takes the next report (waits up to 100 ms for it).
bool read_state(BoxSession& s, device::BoxState& state) {
  while (s.client->poll(state)) {
  }
  for (int i = 0; i < 100; ++i) {
    s.clock.wait(-1, 1000);
    if (s.client->poll(state)) return true;
  }
  return false;
}

int run_calibrate(std::span<const std::string> argv) {
  Args args(argv, {"emu", "travel-mm", "turns", "full-scale-mN", "full-scale-uNm"}, {"json"});
  const auto travel_mm = args.number("travel-mm");
  const auto turns = args.number("turns");
  const auto fs_force = args.integer("full-scale-mN");
  const auto fs_torque = args.integer("full-scale-uNm");
  if (!args.ok()) return fail_usage("calibrate", args.error());
  if (!args.positionals().empty()) return fail_usage("calibrate", "takes no arguments");
  const double travel = travel_mm.value_or(100.0);
  const double revs = turns.value_or(1.0);
  if (travel < 10 || travel > 1000) return fail_usage("calibrate", "--travel-mm must be 10..1000");
  if (revs < 0.25 || revs > 100) return fail_usage("calibrate", "--turns must be 0.25..100");
  if ((fs_force && (*fs_force < 1 || *fs_force > 100000)) || (fs_torque && (*fs_torque < 1 || *fs_torque > 10000000))) {
    return fail_usage("calibrate", "full scale out of range");
  }
  int code = 0;
  auto session = open_box("calibrate", args, code);
  if (!session) return code;
  auto& box = *session->client;
  auto current = box.calibration();
  if (!current) return fail("calibrate", current.error());
  cbx_calibration cal = current.value();

  // With --json the guide goes to stderr, so stdout is the one JSON object.
  std::FILE* guide = args.flag("json") ? stderr : stdout;
  std::fprintf(guide, "Calibrating %s\n", box.describe().c_str());
  if (!wait_enter(guide, "1/3  Put the tool at the start mark and hold it still.")) return fail_usage("calibrate", "input ended; nothing written");
  if (auto reset = box.reset_counters(CBX_RESET_INSERTION_COUNT | CBX_RESET_ROTATION_COUNT); !reset) return fail("calibrate", reset.error());
  device::BoxState state;
  char prompt[160];
  std::snprintf(prompt, sizeof prompt, "2/3  Push the tool exactly %.1f mm (to the end mark) without turning it.", travel);
  if (!wait_enter(guide, prompt)) return fail_usage("calibrate", "input ended; nothing written");
  if (!read_state(*session, state)) return fail("calibrate", device::make_error(device::Errc::kTimeout, "no state from the box"));
  const int32_t insertion_counts = state.report.insertion_count;
  std::snprintf(prompt, sizeof prompt, "3/3  Turn the tool exactly %.2f turn(s) in one direction.", revs);
  if (!wait_enter(guide, prompt)) return fail_usage("calibrate", "input ended; nothing written");
  if (!read_state(*session, state)) return fail("calibrate", device::make_error(device::Errc::kTimeout, "no state from the box"));
  const int32_t rotation_counts = state.report.rotation_count;

  // A real roller gives tens of counts per mm; too few means the tool slipped or did not move.
  if (std::abs(insertion_counts) < 100) {
    return fail("calibrate", device::make_error(device::Errc::kBadArgument,
                                                "insertion moved only " + std::to_string(insertion_counts) +
                                                    " counts: did the tool move (or slip in the rollers)? nothing written"));
  }
  if (std::abs(rotation_counts) < 16) {
    return fail("calibrate", device::make_error(device::Errc::kBadArgument,
                                                "rotation moved only " + std::to_string(rotation_counts) + " counts; nothing written"));
  }
  cal.insertion_counts_per_m = static_cast<uint32_t>(std::lround(std::abs(insertion_counts) * 1000.0 / travel));
  cal.rotation_counts_per_rev = static_cast<uint32_t>(std::lround(std::abs(rotation_counts) / revs));
  if (fs_force) cal.insertion_full_scale_mN = static_cast<uint32_t>(*fs_force);
  if (fs_torque) cal.rotation_full_scale_uNm = static_cast<uint32_t>(*fs_torque);
  if (cal.insertion_full_scale_mN == 0 || cal.rotation_full_scale_uNm == 0) {
    return fail_usage("calibrate", "the box has no actuator full scale yet: give --full-scale-mN and --full-scale-uNm");
  }
  if (cal.insertion_curve[CBX_CURVE_POINTS - 1].in_permille == 0) {  // no curve yet: linear
    for (unsigned i = 0; i < CBX_CURVE_POINTS; ++i) {
      const auto v = static_cast<uint16_t>(250 * (i + 1));
      cal.insertion_curve[i] = {v, v};
      cal.rotation_curve[i] = {v, v};
    }
  }
  if (auto written = box.set_calibration(cal); !written) return fail("calibrate", written.error());
  auto back = box.calibration();
  if (!back) return fail("calibrate", back.error());
  if (back.value().insertion_counts_per_m != cal.insertion_counts_per_m ||
      back.value().rotation_counts_per_rev != cal.rotation_counts_per_rev) {
    return fail("calibrate", device::make_error(device::Errc::kDeviceError, "the box did not keep the calibration"));
  }
  if (args.flag("json")) {
    print_json(Json{{"insertion_counts", int64_t{insertion_counts}},
                    {"rotation_counts", int64_t{rotation_counts}},
                    {"insertion_counts_per_m", cal.insertion_counts_per_m},
                    {"rotation_counts_per_rev", cal.rotation_counts_per_rev}});
  } else {
    std::printf("written: %u counts/m (%.3f counts/mm), %u counts/rev\n", cal.insertion_counts_per_m,
                cal.insertion_counts_per_m / 1000.0, cal.rotation_counts_per_rev);
  }
  return kExitOk;
}

const Registrar registrar({"calibrate", "guided encoder calibration [--emu PATH] [--travel-mm MM] [--turns N] [--json]", run_calibrate});

}  // namespace
}  // namespace cathbox::cli
