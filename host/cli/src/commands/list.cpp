// `cathbox list`: every box the host can reach: real boxes (hidraw), STM32 ROM bootloaders
// (USB 0483:DF11) and the emulator's socket.
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "box_session.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "device/box_client.hpp"
#include "device/box_opener.hpp"
#include "device/hidapi_transport.hpp"
#include "device/libusb_control.hpp"
#include "device/socket_transport.hpp"
#include "protocol/cbx_protocol.h"

namespace cathbox::cli {
namespace {

int run_list(std::span<const std::string> argv) {
  Args args(argv, {"emu"}, {"json"});
  if (!args.ok()) return fail_usage("list", args.error());
  if (!args.positionals().empty()) return fail_usage("list", "takes no arguments");
  Json items = Json::array();
  std::vector<std::string> lines;
  if (auto boxes = device::HidapiTransport::enumerate(); boxes) {
    for (const auto& b : boxes.value()) {
      items.push_back({{"kind", "box"}, {"path", b.path}, {"serial", b.serial}});
      lines.push_back("box         " + b.path + "  serial " + b.serial + "  (" + b.product + ")");
    }
  }
  if (auto loaders = device::LibusbControl::list(); loaders) {
    for (const auto& where : loaders.value()) {
      items.push_back({{"kind", "bootloader"}, {"usb", where}});
      lines.push_back("bootloader  usb " + where + "  (STM32 ROM DFU, 0483:df11)");
    }
  }
  device::SystemClock clock;
  // Every emulator asked for (--emu, repeated: one per box of a rig), else the default socket.
  std::vector<std::string> paths = args.values("emu");
  if (paths.empty()) paths.push_back(device::SocketTransport::default_path());
  for (const std::string& path : paths) {
    auto emu = device::SocketTransport::open(path, clock);
    if (!emu) continue;
    if (emu.value()->pid() != CBX_USB_PID) {
      items.push_back({{"kind", "emulator-bootloader"}, {"socket", path}});
      lines.push_back("emulator    (in DFU bootloader) " + path);
      continue;
    }
    emu.value().reset();  // one connection at a time: the client opens its own
    std::string serial;
    if (auto client = device::BoxClient::connect(device::box_opener(path, clock), clock); client) {
      const cbx_device_info& info = client.value()->device_info();
      serial.assign(info.serial, strnlen(info.serial, sizeof info.serial));
    }
    items.push_back({{"kind", "emulator"}, {"socket", path}, {"serial", serial}});
    lines.push_back("emulator    " + path + "  serial " + (serial.empty() ? "(unknown)" : serial));
  }
  if (args.flag("json")) {
    print_json(items);
  } else if (lines.empty()) {
    std::string where;
    for (const std::string& p : paths) where += (where.empty() ? "" : ", ") + p;
    std::printf("no box found (no hidraw 1209:cb01, no bootloader 0483:df11, no emulator at %s)\n", where.c_str());
  } else {
    for (const auto& line : lines) std::printf("%s\n", line.c_str());
  }
  return items.empty() ? kExitNoDevice : kExitOk;
}

const Registrar registrar({"list", "list boxes (with their serials), bootloaders and emulators [--emu PATH]... [--json]", run_list});

}  // namespace
}  // namespace cathbox::cli
