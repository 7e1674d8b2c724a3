#include "emu/image_emulator.hpp"

#include <algorithm>
#include <cstring>

#include "protocol/cbx_protocol.h"
#include "protocol/cbx_usb_requests.h"

namespace cathbox::emu {
namespace {

constexpr uint64_t kCyclesPerStep = Stm32Machine::kSysclk_Hz / 1'000'000u * ImageEmulator::kPhysicsStep_us;
constexpr uint64_t kControlTimeout_us = 500'000;  // a host gives up on a control stage
constexpr size_t kOutQueue = 64;                  // hidraw's write queue
constexpr uint64_t kAttachDebounce_us = 100'000;

std::array<uint8_t, 8> setup_bytes(const cbx_usb_setup& s) {
  return {s.request_type, s.request, static_cast<uint8_t>(s.value), static_cast<uint8_t>(s.value >> 8),
          static_cast<uint8_t>(s.index), static_cast<uint8_t>(s.index >> 8), static_cast<uint8_t>(s.length),
          static_cast<uint8_t>(s.length >> 8)};
}

}  // namespace

ImageEmulator::ImageEmulator(bool motor, uint64_t seed)
    : bootloader_(dfu_flash_), faults_(seed), wire_version_(CBX_PROTOCOL_VERSION) {
  for (int a = 0; a < 2; ++a) model_.params(a).motor = motor;
}

ImageEmulator::~ImageEmulator() = default;

Result<std::unique_ptr<ImageEmulator>> ImageEmulator::create(std::span<const uint8_t> image, bool motor, uint64_t seed) {
  if (image.size() < 8 || image.size() > Stm32Machine::kFlashSize) {
    return Error{"image of " + std::to_string(image.size()) + " bytes: not an STM32F411 flash image (8 bytes .. 512 KiB)"};
  }
  std::unique_ptr<ImageEmulator> box(new ImageEmulator(motor, seed));
  box->machine_.load_flash(image);
  box->dfu_flash_.erase_sector(0);
  (void)box->dfu_flash_.program(FlashMemory::kBase, image);
  if (!box->dfu_flash_.application_valid()) {
    return Error{"image has no bootable vector table (stack pointer in SRAM, reset vector a Thumb address in flash)"};
  }
  if (!box->machine_.error().empty()) return Error{box->machine_.error()};
  return box;
}

Status ImageEmulator::listen(const std::string& path) {
  auto server = EmuServer::listen(path, *this);
  if (!server) return server.error();
  server_ = std::move(server.value());
  return base::Ok{};
}

void ImageEmulator::step() {
  now_us_ += kPhysicsStep_us;
  Stm32Inputs& in = machine_.inputs();
  std::array<int16_t, 2> drive = bootloader_mode_ ? std::array<int16_t, 2>{0, 0} : machine_.outputs().drive_permille;
  if (in.estop_open) drive = {0, 0};  // the E-stop loop also cuts actuator power
  std::array<int64_t, 2> steps{};
  model_.step(kPhysicsStep_us * 1e-6, now_us_, drive, steps);
  for (size_t a = 0; a < 2; ++a) {
    const int64_t transient = steps[a] != 0 && !bootloader_mode_ ? encoder_noise(a, steps[a]) : 0;
    in.encoder[a] = model_.state(static_cast<int>(a)).count + encoder_lost_[a] + transient;
    in.current_mA[a] = static_cast<int16_t>(model_.current_mA(static_cast<int>(a), drive[a]));
  }
  if (!bootloader_mode_ && machine_.error().empty()) {
    machine_.run(kCyclesPerStep);
    if (machine_.in_bootloader()) enter_bootloader();
  }
  if (now_us_ % kFrame_us == 0) frame();
}

// The encoder lines' noise for one physics step of `steps` transitions: a missed sample loses
// its two counts for good (TIM2/TIM3 count no illegal transition); a bounce is returned as the
// counter's offset for this step (one line toggled: a count either way, undone at the next).
int64_t ImageEmulator::encoder_noise(size_t axis, int64_t steps) {
  const int64_t direction = steps > 0 ? 1 : -1;
  int64_t transient = 0;
  for (int64_t i = 0; i < std::llabs(steps); ++i) {
    if (faults_.chance(faults_.encoder.bounce)) {
      transient = faults_.uniform(2) == 0 ? 1 : -1;
      ++faults_.mutable_counts().bounces;
    } else if (i + 1 < std::llabs(steps) && faults_.chance(faults_.encoder.skip)) {
      encoder_lost_[axis] -= 2 * direction;
      ++faults_.mutable_counts().skips;
      ++i;
    }
  }
  return transient;
}

void ImageEmulator::send_in(std::span<const uint8_t> packet) {
  std::array<uint8_t, 64> report{};
  std::copy_n(packet.begin(), std::min<size_t>(packet.size(), report.size()), report.begin());
  if (packet.size() == CBX_REPORT_SIZE) rewrite_wire_version(report, wire_version_);
  const auto d = faults_.apply(faults_.in, report);
  for (int i = 0; i < d.copies; ++i) {
    if (d.delay_us > 0) {
      in_delayed_.push_back({now_us_ + d.delay_us, report});
    } else if (server_) {
      server_->send_in(std::span<const uint8_t>(report.data(), packet.size()));
    }
  }
}

void ImageEmulator::unplug(uint64_t duration_us) {
  unplugged_until_us_ = now_us_ + duration_us;
  if (bootloader_mode_) return;
  if (enumerated_) detach();
  machine_.otg().suspend();  // no more SOFs: the device's core sees the bus idle
}

void ImageEmulator::frame() {
  while (!in_delayed_.empty() && in_delayed_.front().due_us <= now_us_) {
    if (server_ && enumerated_) server_->send_in(in_delayed_.front().report);
    in_delayed_.pop_front();
  }
  while (!out_delayed_.empty() && out_delayed_.front().due_us <= now_us_) {
    if (enumerated_ && out_queue_.size() < kOutQueue) out_queue_.push_back(out_delayed_.front().report);
    out_delayed_.pop_front();
  }
  if (bootloader_mode_ || !enumerated_) return;
  OtgFs& otg = machine_.otg();
  if (!otg.connected() || otg.disconnects() != disconnects_seen_) {
    detach();
    return;
  }
  if (otg.suspended()) return;  // a suspended bus carries no SOF and no tokens
  otg.sof();
  std::vector<uint8_t> packet;
  if (otg.in(1, packet) == OtgFs::Handshake::kAck) {
    ++in_reports_;
    send_in(packet);
  }
  if (!out_queue_.empty() && otg.out(1, out_queue_.front()) == OtgFs::Handshake::kAck) out_queue_.pop_front();
}

void ImageEmulator::advance(uint64_t us) {
  const uint64_t end = now_us_ + us;
  while (now_us_ < end) {
    step();
    if (now_us_ % kFrame_us != 0) continue;
    if (!bootloader_mode_ && !enumerated_) {
      // The host sees the D+ pull-up, waits out the attach debounce (USB 2.0 7.1.7.3: 100 ms
      // of a stable connection), then resets and enumerates.
      if (now_us_ < unplugged_until_us_ || !machine_.otg().connected() ||
          machine_.otg().disconnects() != disconnects_seen_) {
        disconnects_seen_ = machine_.otg().disconnects();
        connected_since_us_.reset();
      } else if (!connected_since_us_) {
        connected_since_us_ = now_us_;
      } else if (now_us_ - *connected_since_us_ >= kAttachDebounce_us && now_us_ >= retry_at_us_) {
        enumerate();
      }
    }
    service();
  }
}

void ImageEmulator::service() {
  if (server_) server_->poll();
  if (bootloader_mode_ && bootloader_.leave_requested()) leave_bootloader();
}

void ImageEmulator::detach() {
  enumerated_ = false;
  connected_since_us_.reset();
  disconnects_seen_ = machine_.otg().disconnects();
  out_queue_.clear();
  in_delayed_.clear();
  out_delayed_.clear();
  if (server_) server_->detach();
}

void ImageEmulator::bus_reset() {
  machine_.otg().bus_reset();
  for (int i = 0; i < 1000 && machine_.error().empty(); ++i) step();  // 10 ms reset recovery
}

void ImageEmulator::usb_reset() {
  // A host resets a port to recover a device, then enumerates it again (the socket stays up,
  // as a hidraw node does across a port reset with the same descriptors).
  if (bootloader_mode_ || !enumerated_) return;
  enumerate();
}

void ImageEmulator::usb_suspend() { machine_.otg().suspend(); }
void ImageEmulator::usb_resume() { machine_.otg().resume(); }

void ImageEmulator::enumerate() {
  // As the kernel does: reset, device descriptor, address, configuration, SET_IDLE, report descriptor.
  enumerated_ = true;  // control() needs it; cleared again on failure
  auto fail = [&](const char* what) {
    enumerated_ = false;
    enumeration_error_ = std::string("enumeration: ") + what + " failed";
    retry_at_us_ = now_us_ + 1'000'000;
  };
  bus_reset();
  std::vector<uint8_t> reply;
  if (!control({0x80, 6, 0x0100, 0, 18}, {}, reply) || reply.size() != 18 || reply[1] != 1) return fail("GET_DESCRIPTOR(device)");
  vid_ = static_cast<uint16_t>(reply[8] | (reply[9] << 8));
  pid_ = static_cast<uint16_t>(reply[10] | (reply[11] << 8));
  if (!control({0x00, 5, 1, 0, 0}, {}, reply)) return fail("SET_ADDRESS");
  if (machine_.otg().address() != 1) return fail("SET_ADDRESS (address not taken)");
  if (!control({0x80, 6, 0x0200, 0, 9}, {}, reply) || reply.size() != 9) return fail("GET_DESCRIPTOR(configuration)");
  const uint16_t total = static_cast<uint16_t>(reply[2] | (reply[3] << 8));
  if (!control({0x80, 6, 0x0200, 0, total}, {}, reply) || reply.size() != total) return fail("GET_DESCRIPTOR(configuration, full)");
  uint16_t report_length = 0;
  for (size_t i = 0; i + 8 < reply.size(); i += std::max<size_t>(reply[i], 1)) {
    if (reply[i + 1] == 0x21) report_length = static_cast<uint16_t>(reply[i + 7] | (reply[i + 8] << 8));
  }
  if (!control({0x00, 9, 1, 0, 0}, {}, reply)) return fail("SET_CONFIGURATION");
  if (!control({0x21, 0x0A, 0, 0, 0}, {}, reply)) return fail("SET_IDLE");
  if (report_length == 0 || !control({0x81, 6, 0x2200, 0, report_length}, {}, reply)) return fail("GET_DESCRIPTOR(report)");
  report_descriptor_ = reply;
  enumeration_error_.clear();
}

bool ImageEmulator::control(const cbx_usb_setup& setup, std::span<const uint8_t> data, std::vector<uint8_t>& reply) {
  reply.clear();
  if (!enumerated_) return false;
  OtgFs& otg = machine_.otg();
  const std::array<uint8_t, 8> packet = setup_bytes(setup);
  otg.setup(packet);
  const uint64_t deadline = now_us_ + kControlTimeout_us;
  auto wait = [&](auto&& transaction) {
    while (now_us_ < deadline && machine_.error().empty() && !bootloader_mode_) {
      step();
      const OtgFs::Handshake h = transaction();
      if (h != OtgFs::Handshake::kNak) return h == OtgFs::Handshake::kAck;
    }
    return false;
  };
  std::vector<uint8_t> chunk;
  if (setup.request_type & 0x80u) {  // control read: DATA IN until short or complete, then status OUT
    for (;;) {
      if (!wait([&] { return otg.in(0, chunk); })) return false;
      reply.insert(reply.end(), chunk.begin(), chunk.end());
      if (chunk.size() < 64 || reply.size() >= setup.length) break;
    }
    return wait([&] { return otg.out(0, {}); });
  }
  for (size_t sent = 0; sent < data.size() && sent < setup.length; sent += 64) {  // control write: DATA OUT
    const auto piece = data.subspan(sent, std::min<size_t>(64, data.size() - sent));
    if (!wait([&] { return otg.out(0, piece); })) return false;
  }
  if (!wait([&] { return otg.in(0, chunk); })) return false;  // status IN (zero length)
  return chunk.empty();
}

bool ImageEmulator::attached(uint16_t& vid, uint16_t& pid) {
  if (bootloader_mode_) {
    vid = CBX_DFU_VID;
    pid = CBX_DFU_PID;
    return true;
  }
  vid = vid_;
  pid = pid_;
  return enumerated_;
}

void ImageEmulator::on_out(std::span<const uint8_t> report) {
  if (!enumerated_ || report.size() != 64) return;
  std::array<uint8_t, 64> r{};
  std::copy(report.begin(), report.end(), r.begin());
  const auto d = faults_.apply(faults_.out, r);
  for (int i = 0; i < d.copies; ++i) {
    if (d.delay_us > 0) {
      out_delayed_.push_back({now_us_ + d.delay_us, r});
    } else if (out_queue_.size() < kOutQueue) {
      out_queue_.push_back(r);
    }
  }
}

bool ImageEmulator::on_control(const cbx_usb_setup& setup, std::span<const uint8_t> data, std::vector<uint8_t>& reply) {
  if (bootloader_mode_) return bootloader_.control(setup, data, now_us_, reply);
  const bool ok = control(setup, data, reply);
  if (ok && setup.request_type == CBX_USB_HID_GET_TYPE && setup.request == CBX_USB_HID_GET_REPORT &&
      reply.size() == CBX_REPORT_SIZE) {
    rewrite_wire_version(reply, wire_version_);
  }
  return ok;
}

void ImageEmulator::enter_bootloader() {
  // The image jumped into system memory: the ROM's DfuSe bootloader takes the USB port.
  detach();
  bootloader_mode_ = true;
  const std::vector<uint8_t> flash = machine_.flash();
  for (int s = 0; s < static_cast<int>(dfu_flash_.sectors().size()); ++s) dfu_flash_.erase_sector(s);
  (void)dfu_flash_.program(FlashMemory::kBase, flash);
  bootloader_.reset();
}

void ImageEmulator::leave_bootloader() {
  if (server_) server_->detach();
  std::vector<uint8_t> flash(dfu_flash_.size());
  (void)dfu_flash_.read(FlashMemory::kBase, flash);
  bootloader_mode_ = false;
  machine_.load_flash(flash);
  retry_at_us_ = 0;
}

}  // namespace cathbox::emu
