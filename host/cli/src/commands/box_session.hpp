#pragma once
// Shared by the device command groups (list, info, monitor, calibrate, selftest, flash):
// opening the box (--emu PATH or the first real box), mapping errors to exit codes, and a
// small JSON writer for --json.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

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

// Minimal JSON: objects and arrays built as text, keys in insertion order.
class Json {
 public:
  Json& field(const std::string& key, const std::string& text);
  Json& field(const std::string& key, const char* text) { return field(key, std::string(text)); }
  Json& field(const std::string& key, double value);
  Json& field(const std::string& key, int64_t value);
  Json& field(const std::string& key, uint64_t value);
  Json& field(const std::string& key, int value) { return field(key, static_cast<int64_t>(value)); }
  Json& field(const std::string& key, unsigned value) { return field(key, static_cast<uint64_t>(value)); }
  Json& field(const std::string& key, bool value);
  Json& raw(const std::string& key, const std::string& json);  // an object or array built elsewhere
  [[nodiscard]] std::string str() const { return "{" + body_ + "}"; }
  [[nodiscard]] static std::string quote(const std::string& text);
  [[nodiscard]] static std::string array(const std::vector<std::string>& items);

 private:
  void key(const std::string& k);
  std::string body_;
};

// Decoded-state helpers shared by info and monitor.
[[nodiscard]] std::string fault_names(uint16_t faults);
[[nodiscard]] std::string status_names(uint16_t status);
[[nodiscard]] const char* mode_name(uint8_t mode);

}  // namespace cathbox::cli
