// `cathbox monitor`: live encoder counts, mm and degrees, velocities, rendered output, currents,
// status and faults, and the state report rate. Reads only: it sends no commands.
#include <algorithm>
#include <csignal>
#include <cstdio>

#include "box_session.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "session/hand_mapping.hpp"

namespace cathbox::cli {
namespace {

volatile std::sig_atomic_t interrupted = 0;
void on_interrupt(int) { interrupted = 1; }

// When a line is printed: seconds since the start, and the box's report rate since the last line.
struct LineTime {
  double t_s;
  double report_rate_hz;
};

// One monitor line: the state report in counts, mm and degrees, as a JSON object or a table row.
void print_state(const cbx_state_report& r, const session::HandMapping& mapping, device::BoxClient& box, LineTime at, bool json) {
  constexpr double kDegPerRad = 180.0 / 3.14159265358979323846;
  const double hz = at.report_rate_hz;
  const double mm = mapping.insertion_mm_from_counts(r.insertion_count);
  const double mm_s = mapping.insertion_mm_from_counts(r.insertion_vel_cps);
  const double deg = mapping.rotation_rad_from_counts(r.rotation_count) * kDegPerRad;
  const double deg_s = mapping.rotation_rad_from_counts(r.rotation_vel_cps) * kDegPerRad;
  if (json) {
    print_json(Json{{"t_s", json_number(at.t_s)},
                    {"insertion_count", int64_t{r.insertion_count}},
                    {"insertion_mm", json_number(mm)},
                    {"insertion_mm_s", json_number(mm_s)},
                    {"insertion_force_mN", int64_t{r.insertion_force_mN}},
                    {"rotation_count", int64_t{r.rotation_count}},
                    {"rotation_deg", json_number(deg)},
                    {"rotation_deg_s", json_number(deg_s)},
                    {"rotation_torque_uNm", int64_t{r.rotation_torque_uNm}},
                    {"insertion_current_mA", int64_t{r.insertion_current_mA}},
                    {"rotation_current_mA", int64_t{r.rotation_current_mA}},
                    {"mode", mode_name(r.mode)},
                    {"status", status_names(r.status)},
                    {"faults", fault_names(r.faults)},
                    {"encoder_errors", unsigned{r.encoder_errors}},
                    {"rx_errors", unsigned{r.rx_errors}},
                    {"report_rate_hz", json_number(hz)},
                    {"host_rejected", box.stats().rejected()},
                    {"link_up", box.link() == device::Link::kUp}});
  } else {
    std::printf("%7.2f  %10d %9.2f %9.1f %7d  %10d %9.1f %9.1f %9d  %6d %6d  %-28s %-12s %6.0f%s\n", at.t_s,
                r.insertion_count, mm, mm_s, r.insertion_force_mN, r.rotation_count, deg, deg_s, r.rotation_torque_uNm,
                r.insertion_current_mA, r.rotation_current_mA, status_names(r.status).c_str(),
                fault_names(r.faults).c_str(), hz, box.link() == device::Link::kUp ? "" : "  (link down)");
  }
}

int run_monitor(std::span<const std::string> argv) {
  Args args(argv, {"emu", "duration", "rate"}, {"json"});
  const auto duration_s = args.number("duration");
  const auto rate_hz = args.number("rate");
  if (!args.ok()) return fail_usage("monitor", args.error());
  if (!args.positionals().empty()) return fail_usage("monitor", "takes no arguments");
  const double rate = rate_hz.value_or(10.0);
  if (rate <= 0 || rate > 1000) return fail_usage("monitor", "--rate must be in (0, 1000] Hz");
  if (duration_s && (*duration_s <= 0 || *duration_s > kMaxSeconds)) {
    return fail_usage("monitor", "--duration must be in (0, " + std::to_string(static_cast<int>(kMaxSeconds)) + "] s");
  }
  int code = 0;
  auto session = open_box("monitor", args, code);
  if (!session) return code;
  auto& box = *session->client;
  auto& clock = session->clock;
  auto cal = box.calibration();
  if (!cal) return fail("monitor", cal.error());
  const session::HandMapping mapping({cal.value().insertion_counts_per_m, cal.value().rotation_counts_per_rev});
  const bool json = args.flag("json");
  std::signal(SIGINT, on_interrupt);
  std::signal(SIGTERM, on_interrupt);

  const uint64_t start = clock.now_us();
  const uint64_t end = duration_s ? start + static_cast<uint64_t>(*duration_s * 1e6) : UINT64_MAX;
  const auto period = static_cast<uint64_t>(1e6 / rate);
  // One line per period, and the last one at the end of --duration (also when it is shorter
  // than a period). The rate is over the time since the previous line.
  uint64_t next_print = std::min(start + period, end);
  uint64_t last_print = start;
  uint64_t accepted_at_last = box.stats().states_accepted;
  device::BoxState state;
  bool have_state = false;
  if (!json) {
    std::printf("%7s  %10s %9s %9s %7s  %10s %9s %9s %9s  %6s %6s  %-28s %-12s %6s\n", "t s", "ins count", "mm", "mm/s",
                "mN", "rot count", "deg", "deg/s", "uN*m", "I1 mA", "I2 mA", "status", "faults", "Hz");
  }
  for (bool last = false; interrupted == 0 && !last;) {
    have_state = box.poll(state) || have_state;
    const uint64_t now = clock.now_us();
    if (now < next_print) {
      clock.wait(-1, 1000);
      continue;
    }
    last = next_print >= end;
    next_print = std::min(next_print + period, end);
    const double interval_s = std::max<uint64_t>(now - last_print, 1) * 1e-6;
    last_print = now;
    const uint64_t accepted = box.stats().states_accepted;
    const double hz = (accepted - accepted_at_last) / interval_s;
    accepted_at_last = accepted;
    if (!have_state) {
      std::fprintf(stderr, "cathbox monitor: no state from the box (%s)\n", box.describe().c_str());
      continue;
    }
    print_state(state.report, mapping, box, {(now - start) * 1e-6, hz}, json);
    std::fflush(stdout);
  }
  return kExitOk;
}

const Registrar registrar({"monitor", "live counts, mm, degrees, velocity, output, faults, report rate [--emu PATH] [--json] [--duration S] [--rate HZ]", run_monitor});

}  // namespace
}  // namespace cathbox::cli
