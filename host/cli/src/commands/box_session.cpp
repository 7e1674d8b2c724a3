#include "box_session.hpp"

#include <cmath>
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

std::string Json::quote(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      char esc[8];
      std::snprintf(esc, sizeof esc, "\\u%04x", c);
      out += esc;
    } else {
      out += c;
    }
  }
  return out + "\"";
}

std::string Json::array(const std::vector<std::string>& items) {
  std::string out = "[";
  for (size_t i = 0; i < items.size(); ++i) out += (i ? "," : "") + items[i];
  return out + "]";
}

void Json::key(const std::string& k) {
  if (!body_.empty()) body_ += ',';
  body_ += quote(k) + ':';
}

Json& Json::field(const std::string& k, const std::string& text) {
  key(k);
  body_ += quote(text);
  return *this;
}

Json& Json::field(const std::string& k, double value) {
  key(k);
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", std::isfinite(value) ? value : 0.0);
  body_ += text;
  return *this;
}

Json& Json::field(const std::string& k, int64_t value) {
  key(k);
  body_ += std::to_string(value);
  return *this;
}

Json& Json::field(const std::string& k, uint64_t value) {
  key(k);
  body_ += std::to_string(value);
  return *this;
}

Json& Json::field(const std::string& k, bool value) {
  key(k);
  body_ += value ? "true" : "false";
  return *this;
}

Json& Json::raw(const std::string& k, const std::string& json) {
  key(k);
  body_ += json;
  return *this;
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
