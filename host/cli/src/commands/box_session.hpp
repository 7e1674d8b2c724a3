#pragma once
// Shared by the device command groups (list, info, monitor, calibrate, selftest, flash):
// opening the box (--emu PATH or the first real box), mapping errors to exit codes, and
// printing --json.
#include <cmath>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "cli/args.hpp"
#include "device/box_client.hpp"
#include "device/clock.hpp"
#include "device/result.hpp"

namespace cathbox::cli {

// The longest --duration / --timeout a command takes (one day): beyond it, or at or below
// zero, the option is bad input (the microsecond count must fit a uint64_t).
inline constexpr double kMaxSeconds = 86'400.0;

// The exit code for a device error (host/cli/README.md).
[[nodiscard]] int exit_code(device::Errc code);
// Prints "cathbox GROUP: MESSAGE" on stderr and returns the exit code.
int fail(const char* group, const device::Error& error);
int fail_usage(const char* group, const std::string& message);

struct BoxSession {
  device::SystemClock clock;
  std::optional<std::string> emu_path;  // --emu
  std::unique_ptr<device::BoxClient> client;
};

// Connects using --emu (if given) or the first real box; on failure prints and returns the
// exit code through `code`.
[[nodiscard]] std::unique_ptr<BoxSession> open_box(const char* group, const Args& args, int& code);

// --json output: nlohmann-json objects with keys in insertion order, printed on one line
// (shapes: host/cli/README.md, checked by tests/host/cli/json_shape.cpp).
using Json = nlohmann::ordered_json;
// A figure for --json: non-finite values print as 0, so every field keeps its type.
[[nodiscard]] inline double json_number(double value) { return std::isfinite(value) ? value : 0.0; }
// Prints the value on one line of stdout.
void print_json(const Json& value);

// Decoded-state helpers shared by info and monitor.
[[nodiscard]] std::string fault_names(uint16_t faults);
[[nodiscard]] std::string status_names(uint16_t status);
[[nodiscard]] const char* mode_name(uint8_t mode);

}  // namespace cathbox::cli
