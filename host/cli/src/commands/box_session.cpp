#include "box_session.hpp"

#include <cstdio>

#include "cli/exit_codes.hpp"
#include "device/box_opener.hpp"
#include "protocol/cbx_state_report.h"

namespace cathbox::cli {

int exit_code(device::Errc code) {
  using device::Errc;
  switch (code) {
    case Errc::kNoDevice:
    case Errc::kDisconnected:
    case Errc::kTimeout:
    case Errc::kIo: return kExitNoDevice;
    case Errc::kIncompatible: return kExitIncompatible;
    case Errc::kBadImage:
    case Errc::kBadArgument: return kExitBadInput;
    case Errc::kVerify: return kExitFailure;
    case Errc::kStall:
    case Errc::kBadReport:
    case Errc::kDeviceError: return kExitDeviceError;
  }
  return kExitFailure;
}

int fail(const char* group, const device::Error& error) {
  // The incompatible-version line is printed as protocol/README.md gives it.
  if (error.code == device::Errc::kIncompatible) {
    std::fprintf(stderr, "cathbox: %s\n", error.message.c_str());
  } else {
    std::fprintf(stderr, "cathbox %s: %s\n", group, error.message.c_str());
  }
  return exit_code(error.code);
}

int fail_usage(const char* group, const std::string& message) {
  std::fprintf(stderr, "cathbox %s: %s\n", group, message.c_str());
  return kExitBadInput;
}

std::unique_ptr<BoxSession> open_box(const char* group, const Args& args, int& code) {
  auto session = std::make_unique<BoxSession>();
  session->emu_path = args.value("emu");
  auto client = device::BoxClient::connect(device::box_opener(session->emu_path, session->clock), session->clock);
  if (!client) {
    code = fail(group, client.error());
    return nullptr;
  }
  session->client = std::move(client.value());
  code = kExitOk;
  return session;
}

void print_json(const Json& value) {
  // Text from the box is not trusted to be UTF-8: bad bytes print as U+FFFD, never throw.
  std::printf("%s\n", value.dump(-1, ' ', false, Json::error_handler_t::replace).c_str());
}

namespace {
std::string names(uint16_t bits, const char* const* table, int count) {
  std::string out;
  for (int i = 0; i < count; ++i) {
    if (bits & (1u << i)) out += (out.empty() ? "" : ",") + std::string(table[i]);
  }
  return out.empty() ? "-" : out;
}
}  // namespace

std::string fault_names(uint16_t faults) {
  static const char* const table[] = {"watchdog", "estop", "encoder", "overcurrent", "not-calibrated", "bad-command"};
  return names(faults, table, 6);
}

std::string status_names(uint16_t status) {
  static const char* const table[] = {"output", "calibrated", "estop-pressed", "command-fresh", "selftest"};
  return names(status, table, 5);
}

const char* mode_name(uint8_t mode) {
  switch (mode) {
    case CBX_MODE_OFF: return "off";
    case CBX_MODE_BRAKE: return "brake";
    case CBX_MODE_MOTOR: return "motor";
    default: return "invalid";
  }
}

}  // namespace cathbox::cli
