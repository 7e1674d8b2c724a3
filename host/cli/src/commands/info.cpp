// `cathbox info`: what the box says about itself: firmware, serial, board, actuators, encoders,
// calibration, limits and its current state.
#include <cstdio>

#include "box_session.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "device/flasher.hpp"

namespace cathbox::cli {
namespace {

const char* actuator_name(uint8_t a) {
  switch (a) {
    case CBX_ACTUATOR_BRAKE: return "brake";
    case CBX_ACTUATOR_MOTOR: return "motor";
    default: return "none";
  }
}

int run_info(std::span<const std::string> argv) {
  Args args(argv, {"emu"}, {"json"});
  if (!args.ok()) return fail_usage("info", args.error());
  if (!args.positionals().empty()) return fail_usage("info", "takes no arguments");
  int code = 0;
  auto session = open_box("info", args, code);
  if (!session) return code;
  auto& box = *session->client;
  const cbx_device_info& d = box.device_info();
  auto cal = box.calibration();
  if (!cal) return fail("info", cal.error());
  auto lim = box.limits();
  if (!lim) return fail("info", lim.error());
  device::BoxState state;
  for (int i = 0; i < 50 && !box.poll(state); ++i) session->clock.wait(-1, 2000);
  const auto& c = cal.value();
  const auto& l = lim.value();
  char fw[32];
  std::snprintf(fw, sizeof fw, "%u.%u.%u", d.fw_major, d.fw_minor, d.fw_patch);
  if (args.flag("json")) {
    Json j;
    j["transport"] = box.describe();
    j["firmware"] = fw;
    j["protocol"] = std::to_string(CBX_PROTOCOL_VERSION) + "." + std::to_string(d.protocol_minor);
    j["serial"] = d.serial;
    j["board"] = d.board;
    j["insertion_actuator"] = actuator_name(d.insertion_actuator);
    j["rotation_actuator"] = actuator_name(d.rotation_actuator);
    j["insertion_encoder_cpr"] = d.insertion_encoder_cpr;
    j["rotation_encoder_cpr"] = d.rotation_encoder_cpr;
    j["calibration"] = {{"insertion_counts_per_m", c.insertion_counts_per_m},
                        {"rotation_counts_per_rev", c.rotation_counts_per_rev},
                        {"insertion_full_scale_mN", c.insertion_full_scale_mN},
                        {"rotation_full_scale_uNm", c.rotation_full_scale_uNm}};
    j["limits"] = {{"max_force_mN", l.max_force_mN},
                   {"max_torque_uNm", l.max_torque_uNm},
                   {"watchdog_timeout_ms", unsigned{l.watchdog_timeout_ms}},
                   {"insertion_max_current_mA", unsigned{l.insertion_max_current_mA}},
                   {"rotation_max_current_mA", unsigned{l.rotation_max_current_mA}},
                   {"force_slew_mN_per_ms", unsigned{l.force_slew_mN_per_ms}},
                   {"torque_slew_uNm_per_ms", unsigned{l.torque_slew_uNm_per_ms}}};
    j["status"] = status_names(state.report.status);
    j["faults"] = fault_names(state.report.faults);
    j["mode"] = mode_name(state.report.mode);
    print_json(j);
    return kExitOk;
  }
  std::printf("box          %s\n", box.describe().c_str());
  std::printf("firmware     %s (protocol v%u.%u)\n", fw, CBX_PROTOCOL_VERSION, d.protocol_minor);
  std::printf("serial       %s\nboard        %s\n", d.serial, d.board);
  std::printf("actuators    insertion %s, rotation %s\n", actuator_name(d.insertion_actuator), actuator_name(d.rotation_actuator));
  std::printf("encoders     insertion %u, rotation %u counts per encoder revolution\n", d.insertion_encoder_cpr, d.rotation_encoder_cpr);
  if (c.insertion_counts_per_m == 0 || c.rotation_counts_per_rev == 0) {
    std::printf("calibration  NOT CALIBRATED (force output blocked): run 'cathbox calibrate'\n");
  } else {
    std::printf("calibration  %u counts/m (%.2f counts/mm), %u counts/rev; full scale %u mN, %u uN*m\n",
                c.insertion_counts_per_m, c.insertion_counts_per_m / 1000.0, c.rotation_counts_per_rev,
                c.insertion_full_scale_mN, c.rotation_full_scale_uNm);
  }
  std::printf("limits       force %u mN, torque %u uN*m, watchdog %u ms, current %u/%u mA, slew %u mN/ms, %u uN*m/ms\n",
              l.max_force_mN, l.max_torque_uNm, l.watchdog_timeout_ms, l.insertion_max_current_mA,
              l.rotation_max_current_mA, l.force_slew_mN_per_ms, l.torque_slew_uNm_per_ms);
  std::printf("state        mode %s, status %s, faults %s\n", mode_name(state.report.mode),
              status_names(state.report.status).c_str(), fault_names(state.report.faults).c_str());
  if ((state.report.board_faults & CBX_BOARD_FAULT_HSE) != 0) {
    std::printf("board faults hse: the crystal did not start; the box runs on its internal oscillator\n");
  }
  return kExitOk;
}

const Registrar registrar({"info", "firmware, serial, calibration, limits and state [--emu PATH] [--json]", run_info});

}  // namespace
}  // namespace cathbox::cli
