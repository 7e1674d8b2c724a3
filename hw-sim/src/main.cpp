// cathbox-emu: the emulated box, served in real time on a Unix-domain socket.
#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cstdint>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <cstdlib>
#include <string>
#include <utility>
#include <vector>

#include <CLI/CLI.hpp>

#include "emu/dfuse_image.hpp"
#include "emu/emulator.hpp"
#include "emu/hand_model.hpp"
#include "emu/image_emulator.hpp"
#include "emu/real_time_loop.hpp"
#include "protocol/cbx_emu_frame.h"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_usb_requests.h"

namespace {

std::atomic<bool> stop_requested{false};  // lock-free: safe to set from a signal handler
void on_signal(int) { stop_requested.store(true); }

bool parse_probability(const std::string& text, double& out) {
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && out >= 0 && out <= 1;
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
bool parse_seconds(const std::string& text, double& out) {
  char* end = nullptr;
  out = std::strtod(text.c_str(), &end);
  return end != text.c_str() && *end == '\0' && std::isfinite(out) && out > 0 && out <= 365.0 * 86400.0;
}

// What the command line sets.
struct Settings {
  cathbox::emu::EmuOptions options;
  std::string path;
  std::string hand[2];
  cathbox::emu::HandModel hand_model = cathbox::emu::HandModel::kScripted;
  double drop = 0, duplicate = 0, corrupt = 0, delay_p = 0, bounce = 0;
  uint64_t delay_us = 0;
  long long estop_after_ms = -1;
  int wire_version = CBX_PROTOCOL_VERSION;
  double duration_s = 0;
  bool help = false;
  std::string image;     // --image / --board: run this firmware image on the emulated STM32F411
  bool trace_mmio = false;
  bool crystal_fails = false;  // --crystal-fails: with --image, the HSE never starts
  bool factory_calibrated = false;  // --calibrated: with --image, calibrate it before serving
};

// An option with a value: its help line and how the value is checked and kept (false: a bad
// value).
struct ValueOption {
  const char* name;
  const char* value_name;
  const char* help;
  bool (*apply)(const std::string& value, Settings& s);
};

const ValueOption kValueOptions[] = {
    {"--socket", "PATH",
     "socket path (default $CATHBOX_EMU_SOCKET, $XDG_RUNTIME_DIR/cathbox-emu.sock, or /tmp/cathbox-emu.sock)",
     [](const std::string& v, Settings& s) { s.path = v; return true; }},
    {"--serial", "TEXT", "serial number reported in device info (default EMU-0001)",
     [](const std::string& v, Settings& s) { s.options.serial = v; return true; }},
    {"--hand-insertion", "S", "scripted hand on the insertion axis, e.g. v:20mm/s:2s,f:-1500mN:500ms,free:1s",
     [](const std::string& v, Settings& s) { s.hand[0] = v; return true; }},
    {"--hand-rotation", "S", "same for rotation (rad/s, mNmm)",
     [](const std::string& v, Settings& s) { s.hand[1] = v; return true; }},
    {"--hand-model", "NAME",
     "how the hand holds the tool: scripted (400 N/m grip, a pure force when pushing; default) or finger (a "
     "fingertip's measured mass, damping and stiffness)",
     [](const std::string& v, Settings& s) {
       const auto model = cathbox::emu::parse_hand_model(v);
       if (model) s.hand_model = *model;
       return model.has_value();
     }},
    {"--drop", "P", "probability of dropping a report (both directions)",
     [](const std::string& v, Settings& s) { return parse_probability(v, s.drop); }},
    {"--duplicate", "P", "probability of sending a report twice (both directions)",
     [](const std::string& v, Settings& s) { return parse_probability(v, s.duplicate); }},
    {"--corrupt", "P", "probability of corrupting a report (both directions)",
     [](const std::string& v, Settings& s) { return parse_probability(v, s.corrupt); }},
    {"--delay", "P:US", "hold a report back US microseconds with probability P",
     [](const std::string& v, Settings& s) {
       const size_t colon = v.find(':');
       unsigned long long us = 0;
       const bool ok = colon != std::string::npos && parse_probability(v.substr(0, colon), s.delay_p) &&
                       parse_count(v.c_str() + colon + 1, 10'000'000ull, us);
       s.delay_us = us;
       return ok;
     }},
    {"--encoder-bounce", "P", "encoder line chatter per transition",
     [](const std::string& v, Settings& s) { return parse_probability(v, s.bounce); }},
    {"--estop-after", "MS", "press the E-stop after MS milliseconds",
     [](const std::string& v, Settings& s) {
       unsigned long long ms = 0;
       const bool ok = parse_count(v.c_str(), 365ull * 86'400'000ull, ms);
       s.estop_after_ms = static_cast<long long>(ms);
       return ok;
     }},
    {"--seed", "N", "seed of the fault injection (default 1)",
     [](const std::string& v, Settings& s) {
       unsigned long long seed = 0;
       const bool ok = parse_count(v.c_str(), UINT64_MAX, seed);
       s.options.seed = seed;
       return ok;
     }},
    {"--wire-version", "N", "send reports with protocol major N (tests the host's version check)",
     [](const std::string& v, Settings& s) {
       unsigned long long version = 0;
       const bool ok = parse_count(v.c_str(), 255, version);
       s.wire_version = static_cast<int>(version);
       return ok;
     }},
    {"--image", "FILE", "run this STM32F411 firmware image (.bin, or a DfuSe .dfu as cathbox flash pack writes it) on the emulated chip instead of the core on a simulated board",
     [](const std::string& v, Settings& s) { s.image = v; return true; }},
    {"--board", "NAME", "run the image the firmware build made for board NAME (stm32f411: build/stm32f411/bin/stm32f411_firmware.bin)",
     [](const std::string& v, Settings& s) {
       if (v != "stm32f411") return false;
       s.image = "@stm32f411";
       return true;
     }},
    {"--duration", "S", "exit after S seconds (default: run until SIGINT/SIGTERM)",
     [](const std::string& v, Settings& s) { return parse_seconds(v, s.duration_s); }},
};

// Parses the command line with CLI11; on bad usage prints one line and returns false.
bool parse_command_line(int argc, char** argv, Settings& s) {
  CLI::App app("Runs the emulated Cathbox (firmware core on a simulated board) in real time and serves it on a "
               "Unix-domain socket, as `cathbox --emu PATH` and the trainer expect.",
               "cathbox-emu");
  app.set_help_flag("-h,--help", "this text");
  app.allow_extras();
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeLast);
  app.get_formatter()->column_width(24);
  CLI::Option* motor = app.add_flag("--motor")->description("DC motors on both axes (default: magnetic-particle brakes)");
  CLI::Option* uncalibrated = app.add_flag("--uncalibrated")->description("start with an empty settings store");
  CLI::Option* trace = app.add_flag("--trace-mmio")->description("with --image: log every peripheral register access to stderr");
  CLI::Option* crystal =
      app.add_flag("--crystal-fails")->description("with --image: the 25 MHz crystal never starts (the image falls back to HSI)");
  CLI::Option* calibrated = app.add_flag("--calibrated")->description(
      "with --image: calibrate the image from the model before serving, as a factory would (saved in its flash)");
  for (CLI::Option* flag : {motor, uncalibrated, trace, crystal, calibrated}) flag->disable_flag_override();
  std::vector<CLI::Option*> values;
  for (const ValueOption& v : kValueOptions) {
    values.push_back(app.add_option(v.name)->expected(0, 1)->type_name(v.value_name)->description(v.help));
  }
  auto incomplete = [](const std::string& word) {
    std::fprintf(stderr, "cathbox-emu: bad or incomplete option '%s' (see --help)\n", word.c_str());
    return false;
  };
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    s.help = true;
    return true;
  } catch (const CLI::Error&) {  // a value given to a flag (`--motor=1`)
    char** const end = argv + argc;
    char** const given = std::find_if(argv + 1, end, [](const char* a) { return std::strchr(a, '=') != nullptr; });
    return incomplete(given == end ? "" : *given);
  }
  if (const std::vector<std::string> extra = app.remaining(); !extra.empty()) return incomplete(extra.front());
  s.options.motor = motor->count() > 0;
  s.options.calibrated = uncalibrated->count() == 0;
  s.trace_mmio = trace->count() > 0;
  s.crystal_fails = crystal->count() > 0;
  s.factory_calibrated = calibrated->count() > 0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    if (values[i]->count() == 0) continue;
    const std::string value = values[i]->as<std::string>();
    if (value.empty()) return incomplete(kValueOptions[i].name);
    if (!kValueOptions[i].apply(value, s)) {
      std::fprintf(stderr, "cathbox-emu: option %s: bad value '%s' (see --help)\n", kValueOptions[i].name, value.c_str());
      return false;
    }
  }
  return true;
}

uint64_t wall_us() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::microseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

// The --hand-insertion / --hand-rotation scripts onto either box; false (after one line on
// stderr) for a bad script.
template <class Box>
bool apply_hand_scripts(const Settings& settings, Box& emu) {
  for (int a = 0; a < 2; ++a) {
    if (settings.hand[a].empty()) continue;
    auto script = cathbox::emu::HandScript::parse(settings.hand[a], a);
    if (!script) {
      std::fprintf(stderr, "cathbox-emu: %s\n", script.error().message.c_str());
      return false;
    }
    emu.set_hand(a, script.value());
  }
  return true;
}

// The fault options, on either box (Emulator or ImageEmulator).
template <typename Box>
void apply_faults(const Settings& settings, Box& box) {
  for (auto* link : {&box.faults().in, &box.faults().out}) {
    link->drop = settings.drop;
    link->duplicate = settings.duplicate;
    link->corrupt = settings.corrupt;
    link->delay = settings.delay_p;
    link->delay_us = settings.delay_us;
  }
  box.faults().encoder.bounce = settings.bounce;
  box.set_wire_version(static_cast<uint8_t>(settings.wire_version));
}

// The image `--board stm32f411` names: what `scripts/build stm32f411` made, beside this build.
std::string board_image(const char* argv0) {
  std::string exe = argv0;
  char resolved[4096];
  if (::realpath("/proc/self/exe", resolved) != nullptr) exe = resolved;
  const size_t bin = exe.rfind('/');
  const std::string dir = bin == std::string::npos ? "." : exe.substr(0, bin);
  return dir + "/../../stm32f411/bin/stm32f411_firmware.bin";
}

// --calibrated: boots the image, sends it the model's calibration (feature report 0x11, as
// `cathbox calibrate` does), reads it back at once (the image answers during its save) and
// lets the main loop finish the save to its flash store (about 1 ms of word programs).
bool factory_calibrate(cathbox::emu::ImageEmulator& emu) {
  emu.advance(300'000);
  if (!emu.enumerated()) return false;
  cbx_calibration calibration = cathbox::emu::model_calibration(emu.model());
  calibration.header.version = CBX_PROTOCOL_VERSION;
  uint8_t report[CBX_REPORT_SIZE] = {};
  if (cbx_calibration_encode(&calibration, report) != CBX_OK) return false;
  const auto value = static_cast<uint16_t>(CBX_USB_HID_REPORT_FEATURE << 8 | CBX_ID_CALIBRATION);
  const cbx_usb_setup set{CBX_USB_HID_SET_TYPE, CBX_USB_HID_SET_REPORT, value, 0, static_cast<uint16_t>(sizeof report)};
  std::vector<uint8_t> reply;
  if (!emu.control(set, report, reply)) return false;
  const cbx_usb_setup get{CBX_USB_HID_GET_TYPE, CBX_USB_HID_GET_REPORT, value, 0, static_cast<uint16_t>(sizeof report)};
  if (!emu.control(get, {}, reply) || reply.size() != sizeof report) return false;
  cbx_calibration back{};
  if (cbx_calibration_decode(reply.data(), reply.size(), &back) != CBX_OK ||
      back.insertion_counts_per_m != calibration.insertion_counts_per_m) {
    return false;
  }
  emu.advance(20'000);
  return emu.error().empty() && emu.enumerated();
}

// cathbox-emu --image: the firmware image on the emulated STM32F411.
int run_image(const Settings& settings, const std::string& path, const char* argv0) {
  const std::string file = settings.image == "@stm32f411" ? board_image(argv0) : settings.image;
  std::FILE* f = std::fopen(file.c_str(), "rb");
  if (f == nullptr) {
    std::fprintf(stderr, "cathbox-emu: cannot read image %s: %s\n", file.c_str(), std::strerror(errno));
    return 2;
  }
  std::vector<uint8_t> image;
  uint8_t buffer[4096];
  for (size_t n; (n = std::fread(buffer, 1, sizeof buffer, f)) > 0;) image.insert(image.end(), buffer, buffer + n);
  std::fclose(f);
  if (cathbox::emu::is_dfuse_name(file)) {
    auto dfu = cathbox::emu::read_dfuse(image, file);
    if (!dfu) {
      std::fprintf(stderr, "cathbox-emu: %s\n", dfu.error().message.c_str());
      return 2;
    }
    image = std::move(dfu.value().flash);
  }
  auto created = cathbox::emu::ImageEmulator::create(image, settings.options.motor, settings.options.seed);
  if (!created) {
    std::fprintf(stderr, "cathbox-emu: %s: %s\n", file.c_str(), created.error().message.c_str());
    return 2;
  }
  cathbox::emu::ImageEmulator& emu = *created.value();
  emu.machine().inputs().crystal_fails = settings.crystal_fails;
  if (settings.trace_mmio) emu.machine().set_trace([](const std::string& line) { std::fprintf(stderr, "%s\n", line.c_str()); });
  if (settings.factory_calibrated && !factory_calibrate(emu)) {
    std::fprintf(stderr, "cathbox-emu: %s: the image did not take the factory calibration%s%s\n", file.c_str(),
                 emu.error().empty() ? "" : ": ", emu.error().c_str());
    return 4;
  }
  if (!apply_hand_scripts(settings, emu)) return 2;
  apply_faults(settings, emu);  // after the factory calibration, which a real factory does on a clean link
  if (auto listening = emu.listen(path); !listening) {
    std::fprintf(stderr, "cathbox-emu: %s\n", listening.error().message.c_str());
    return 3;
  }
  std::printf("cathbox-emu: running %s on the emulated STM32F411; listening on %s\n", file.c_str(), path.c_str());
  std::fflush(stdout);
  const uint64_t estop_at_us =
      settings.estop_after_ms >= 0 ? static_cast<uint64_t>(settings.estop_after_ms) * 1000u : UINT64_MAX;
  bool enumerated = false;
  cathbox::emu::RealTimeLoop::run_box(emu, stop_requested,
                                      settings.duration_s > 0 ? static_cast<uint64_t>(settings.duration_s * 1e6) : 0,
                                      [&](uint64_t now_us) {
                                        if (now_us >= estop_at_us) emu.set_estop(true);
                                        if (!emu.error().empty()) stop_requested.store(true);
                                        if (emu.enumerated() != enumerated) {
                                          enumerated = emu.enumerated();
                                          std::printf("cathbox-emu: the image %s at %.3f s\n",
                                                      enumerated ? "enumerated" : "detached", now_us * 1e-6);
                                          std::fflush(stdout);
                                        }
                                      });
  if (!emu.error().empty()) {
    std::fprintf(stderr, "cathbox-emu: the image stopped at %.3f s: %s\n", emu.now_us() * 1e-6, emu.error().c_str());
    return 4;
  }
  std::printf("cathbox-emu: stopped; %llu IN reports sent\n", static_cast<unsigned long long>(emu.in_reports_sent()));
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  using cathbox::emu::Emulator;
  Settings settings;
  if (!parse_command_line(argc, argv, settings)) return 2;
  if (settings.help) return 0;
  std::string& path = settings.path;
  if (path.empty()) {
    char buffer[108];
    if (cbx_emu_default_socket_path(buffer, sizeof buffer) != CBX_OK) {
      std::fprintf(stderr, "cathbox-emu: default socket path too long; use --socket\n");
      return 2;
    }
    path = buffer;
  }

  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  std::signal(SIGPIPE, SIG_IGN);
  if (!settings.image.empty()) return run_image(settings, path, argv[0]);
  Emulator emu(settings.options);
  cathbox::emu::apply_hand_model(settings.hand_model, emu.model().params(0));
  if (!apply_hand_scripts(settings, emu)) return 2;
  apply_faults(settings, emu);
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
  const uint64_t estop_at_us =
      settings.estop_after_ms >= 0 ? static_cast<uint64_t>(settings.estop_after_ms) * 1000u : UINT64_MAX;
  cathbox::emu::RealTimeLoop::run(emu, stop_requested, settings.duration_s > 0 ? static_cast<uint64_t>(settings.duration_s * 1e6) : 0,
                                  [&](uint64_t now_us) {
                                    if (now_us >= estop_at_us) emu.set_estop(true);
                                  });
  std::printf("cathbox-emu: stopped after %.1f s, %llu IN reports sent\n", (wall_us() - start) * 1e-6,
              static_cast<unsigned long long>(emu.in_reports_sent()));
  return 0;
}
