// `cathbox flash FIRMWARE.dfu`: checks the image, brings the box into the STM32 ROM DFU
// bootloader (by request, or through BOOT0/NRST with --recover-gpio), erases, downloads,
// verifies and starts the new firmware. `cathbox flash pack BIN DFU` wraps the firmware build's
// .bin into a checked .dfu file carrying the image's own version (`--version X.Y` must agree).
#include <cstdio>
#include <fstream>
#include <iterator>

#include "box_session.hpp"
#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"
#include "device/box_opener.hpp"
#include "device/dfu_file.hpp"
#include "device/flasher.hpp"
#include "device/gpiod_boot_pins.hpp"
#include "device/libusb_control.hpp"
#include "device/socket_transport.hpp"
#include "protocol/cbx_image_info.h"
#include "protocol/cbx_protocol.h"

namespace cathbox::cli {
namespace {

constexpr std::int64_t kEnumerateTimeout_us = 5'000'000;

// Parses "MAJOR.MINOR" into BCD (0xMMmm).
bool parse_version(const std::string& text, uint16_t& bcd) {
  unsigned major = 0;
  unsigned minor = 0;
  char extra = 0;
  if (std::sscanf(text.c_str(), "%u.%u%c", &major, &minor, &extra) != 2 || major > 99 || minor > 99) return false;
  bcd = static_cast<uint16_t>(((major / 10) << 12) | ((major % 10) << 8) | ((minor / 10) << 4) | (minor % 10));
  return true;
}

// The image's own version (its info block, protocol/README.md) as BCD major.minor, or a
// one-line reason it has none.
device::Result<uint16_t> image_version_bcd(const std::vector<uint8_t>& bin, const std::string& path) {
  cbx_image_info info{};
  if (bin.size() < CBX_IMAGE_INFO_OFFSET + CBX_IMAGE_INFO_SIZE ||
      cbx_image_info_decode(bin.data() + CBX_IMAGE_INFO_OFFSET, CBX_IMAGE_INFO_SIZE, &info) != CBX_OK) {
    return device::make_error(device::Errc::kBadImage,
                              path + ": no image info block at offset 0x200 (not a Cathbox firmware image): its version is unknown");
  }
  if (info.fw_major > 99 || info.fw_minor > 99) {
    return device::make_error(device::Errc::kBadImage, path + ": image version " + std::to_string(info.fw_major) + "." +
                                                           std::to_string(info.fw_minor) + " does not fit a DFU bcdDevice");
  }
  return static_cast<uint16_t>(((info.fw_major / 10) << 12) | ((info.fw_major % 10) << 8) | ((info.fw_minor / 10) << 4) |
                               (info.fw_minor % 10));
}

int run_pack(const Args& args) {
  if (args.positionals().size() != 3) return fail_usage("flash", "usage: cathbox flash pack FIRMWARE.bin OUT.dfu [--version MAJOR.MINOR]");
  const std::string& in_path = args.positionals()[1];
  const std::string& out_path = args.positionals()[2];
  std::ifstream in(in_path, std::ios::binary);
  if (!in) return fail_usage("flash", in_path + ": cannot open");
  std::vector<uint8_t> bin((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  // The DFU file's version is the image's own: a --version that differs would make the DFU
  // file contradict what the flashed box reports.
  auto own = image_version_bcd(bin, in_path);
  if (!own) return fail("flash", own.error());
  const uint16_t bcd = own.value();
  if (args.value("version")) {
    uint16_t asked = 0;
    if (!parse_version(*args.value("version"), asked)) {
      return fail_usage("flash", "pack --version: bad value '" + *args.value("version") + "' (MAJOR.MINOR, e.g. 1.0)");
    }
    if (asked != bcd) {
      return fail_usage("flash", in_path + ": --version " + device::Flasher::version_text(asked) +
                                     " differs from the image's own version " + device::Flasher::version_text(bcd) +
                                     " (its info block); rebuild the image with that version, or leave --version out");
    }
  }
  device::DfuImage image;
  image.bcd_device = bcd;
  image.vid = CBX_DFU_VID;
  image.pid = CBX_DFU_PID;
  image.target_name = device::FirmwareTarget{}.name;
  image.elements.push_back({device::FirmwareTarget{}.flash_base, std::move(bin)});
  if (auto checked = device::Flasher::check_image(image, {}); !checked) {
    return fail("flash", device::make_error(checked.error().code, in_path + ": " + checked.error().message));
  }
  const auto bytes = device::DfuFile::write(image);
  std::ofstream out(out_path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  if (!out) return fail_usage("flash", out_path + ": cannot write");
  std::printf("packed %zu bytes of firmware %s into %s\n", image.total_bytes(), device::Flasher::version_text(bcd).c_str(),
              out_path.c_str());
  return kExitOk;
}

// The emulator's bootloader: ask the application to enter it if needed, then reconnect.
device::Result<std::unique_ptr<device::SocketTransport>> emulated_bootloader(const std::string& path, device::Clock& clock) {
  auto first = device::SocketTransport::open(path, clock);
  if (!first) return first.error();
  if (first.value()->pid() == CBX_DFU_PID) return std::move(first.value());
  first.value().reset();
  auto box = device::BoxClient::connect(device::box_opener(path, clock), clock);
  if (!box) return box.error();
  std::printf("box %s: firmware %u.%u.%u, entering the bootloader\n", box.value()->describe().c_str(),
              box.value()->device_info().fw_major, box.value()->device_info().fw_minor, box.value()->device_info().fw_patch);
  if (auto entered = box.value()->enter_bootloader(); !entered) return entered.error();
  const std::int64_t deadline = clock.now_us() + kEnumerateTimeout_us;
  while (clock.now_us() < deadline) {
    auto dfu = device::SocketTransport::open(path, clock);
    if (dfu && dfu.value()->pid() == CBX_DFU_PID) return std::move(dfu.value());
    clock.wait(-1, 50'000);
  }
  return device::make_error(device::Errc::kNoDevice, "the emulated box did not come back as a bootloader");
}

// A real box: bootloader already there, or by GPIO strapping, or by request to the firmware.
device::Result<std::unique_ptr<device::LibusbControl>> usb_bootloader(const Args& args, device::Clock& clock,
                                                                      std::unique_ptr<device::GpiodBootPins>& pins) {
  if (auto gpio = args.value("recover-gpio")) {
    auto config = device::GpioConfig::parse(*gpio);
    if (!config) return config.error();
    auto opened = device::GpiodBootPins::open(config.value());
    if (!opened) return opened.error();
    pins = std::move(opened.value());
    std::printf("recovery: BOOT0 high, reset pulse on %s lines %u/%u\n", config.value().chip.c_str(),
                config.value().boot0_line, config.value().nrst_line);
    if (auto entered = device::BootRecovery::enter_bootloader(*pins); !entered) return entered.error();
    return device::LibusbControl::open(5000);
  }
  if (auto present = device::LibusbControl::open(0)) return present;
  auto box = device::BoxClient::connect(device::box_opener(std::nullopt, clock), clock);
  if (!box) return box.error();
  std::printf("box %s: entering the bootloader\n", box.value()->describe().c_str());
  if (auto entered = box.value()->enter_bootloader(); !entered) return entered.error();
  return device::LibusbControl::open(5000);
}

int run_flash(std::span<const std::string> argv) {
  Args args(argv, {"emu", "recover-gpio", "version"}, {});
  if (!args.ok()) return fail_usage("flash", args.error());
  if (!args.positionals().empty() && args.positionals()[0] == "pack") return run_pack(args);
  if (args.positionals().size() != 1) {
    return fail_usage("flash", "usage: cathbox flash FIRMWARE.dfu [--emu PATH] [--recover-gpio CHIP:BOOT0:NRST]");
  }
  if (args.value("emu") && args.value("recover-gpio")) {
    return fail_usage("flash", "--recover-gpio drives real GPIO lines; it cannot be combined with --emu");
  }
  // Every check of the image happens before the box is touched.
  auto image = device::DfuFile::load(args.positionals()[0]);
  if (!image) return fail("flash", image.error());
  const device::FirmwareTarget target;
  if (auto checked = device::Flasher::check_image(image.value(), target); !checked) return fail("flash", checked.error());
  std::printf("image %s: firmware %s for '%s', %zu bytes\n", args.positionals()[0].c_str(),
              device::Flasher::version_text(image.value().bcd_device).c_str(), image.value().target_name.c_str(),
              image.value().total_bytes());

  device::SystemClock clock;
  std::unique_ptr<device::ControlTransfer> usb;
  std::unique_ptr<device::GpiodBootPins> pins;
  if (auto emu = args.value("emu")) {
    auto dfu = emulated_bootloader(*emu, clock);
    if (!dfu) return fail("flash", dfu.error());
    usb = std::move(dfu.value());
  } else {
    auto dfu = usb_bootloader(args, clock, pins);
    if (!dfu) return fail("flash", dfu.error());
    usb = std::move(dfu.value());
  }
  std::printf("bootloader %s\n", usb->describe().c_str());
  std::string last_step;
  auto progress = [&](const std::string& step, size_t done, size_t total) {
    if (step != last_step && !last_step.empty()) std::fprintf(stderr, "\n");
    last_step = step;
    std::fprintf(stderr, "\r%-7s %zu/%zu", step.c_str(), done, total);
  };
  auto flashed = device::Flasher::flash(*usb, image.value(), target, progress);
  std::fprintf(stderr, "\n");
  usb.reset();
  if (!flashed) return fail("flash", flashed.error());
  std::printf("flashed %zu bytes (%zu sectors erased), verified %zu bytes\n", flashed.value().bytes_written,
              flashed.value().sectors_erased, flashed.value().bytes_verified);
  if (pins) {
    if (auto app = device::BootRecovery::run_application(*pins); !app) return fail("flash", app.error());
  }
  // The new firmware enumerates again.
  const std::int64_t deadline = clock.now_us() + kEnumerateTimeout_us;
  for (;;) {
    auto box = device::BoxClient::connect(device::box_opener(args.value("emu"), clock), clock);
    if (box) {
      const auto& d = box.value()->device_info();
      std::printf("box is back: firmware %u.%u.%u, serial %s\n", d.fw_major, d.fw_minor, d.fw_patch, d.serial);
      return kExitOk;
    }
    if (box.error().code == device::Errc::kIncompatible || clock.now_us() > deadline) return fail("flash", box.error());
    clock.wait(-1, 100'000);
  }
}

const Registrar registrar({"flash", "flash firmware: FIRMWARE.dfu [--emu PATH] [--recover-gpio CHIP:BOOT0:NRST]; pack BIN DFU [--version X.Y]", run_flash});

}  // namespace
}  // namespace cathbox::cli
