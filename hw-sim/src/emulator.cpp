#include "emu/emulator.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>

#include "firmware/cbx_core.h"
#include "protocol/cbx_bytes.h"
#include "protocol/cbx_image_info.h"
#include "protocol/cbx_usb_requests.h"

namespace cathbox::emu {

struct Emulator::Core {
  cbx_core c;
};

namespace {

// Gray-code order of the A/B lines (bit 0 = A, bit 1 = B) for increasing counts.
constexpr std::array<uint8_t, 4> kQuadrature = {0b00, 0b01, 0b11, 0b10};

// A small factory image: a vector table (stack at the top of SRAM, reset handler in flash),
// the image info block of this firmware core's version, and filler, so the ROM sees a bootable
// application and `cathbox info` the version the board left the factory with.
void factory_image(FlashMemory& flash) {
  std::vector<uint8_t> image(1024, 0x00);
  const uint32_t sp = 0x20020000u;
  const uint32_t reset = 0x08000199u;
  cbx_put_u32(image.data(), sp);
  cbx_put_u32(image.data() + 4, reset);
  cbx_image_info info{};
  info.fw_major = CBX_FW_MAJOR;
  info.fw_minor = CBX_FW_MINOR;
  info.fw_patch = CBX_FW_PATCH;
  info.protocol_minor = CBX_PROTOCOL_MINOR;
  std::snprintf(info.board, sizeof info.board, "cathbox-emu");
  std::snprintf(info.build, sizeof info.build, "factory");
  info.image_size = static_cast<uint32_t>(image.size());
  if (cbx_image_info_encode(&info, image.data() + CBX_IMAGE_INFO_OFFSET) != CBX_OK) std::abort();
  flash.load(FlashMemory::kBase, image);
}

cbx_curve_point linear(int i) {
  const auto v = static_cast<uint16_t>(250 * (i + 1));
  return {v, v};
}

}  // namespace

cbx_calibration model_calibration(BoxModel& model) {
  cbx_calibration cal{};
  cal.header.version = CBX_PROTOCOL_VERSION;
  cal.insertion_counts_per_m = static_cast<uint32_t>(std::lround(model.params(0).counts_per_unit));
  cal.rotation_counts_per_rev = static_cast<uint32_t>(std::lround(model.params(1).counts_per_unit * 2.0 * M_PI));
  cal.insertion_full_scale_mN = static_cast<uint32_t>(std::lround(model.params(0).full_scale * 1e3));
  cal.rotation_full_scale_uNm = static_cast<uint32_t>(std::lround(model.params(1).full_scale * 1e6));
  for (int i = 0; i < static_cast<int>(CBX_CURVE_POINTS); ++i) {
    cal.insertion_curve[i] = linear(i);
    cal.rotation_curve[i] = linear(i);
  }
  return cal;
}

Emulator::Emulator(EmuOptions options)
    : options_(std::move(options)), core_(std::make_unique<Core>()), bootloader_(flash_), faults_(options_.seed) {
  factory_image(flash_);
  if (options_.calibrated) {
    // The board's settings store, as `cathbox calibrate` would have left it.
    const cbx_calibration cal = model_calibration(model_);
    cbx_settings defaults;
    cbx_core_default_settings(&defaults);
    defaults.limits.header.version = CBX_PROTOCOL_VERSION;
    board_.store.resize(2 * CBX_REPORT_SIZE);
    (void)cbx_calibration_encode(&cal, board_.store.data());
    (void)cbx_limits_encode(&defaults.limits, board_.store.data() + CBX_REPORT_SIZE);
  }
  for (int a = 0; a < 2; ++a) model_.params(a).motor = options_.motor;
  boot(false);
}

Emulator::~Emulator() = default;

Status Emulator::listen(const std::string& path) {
  auto server = EmuServer::listen(path, *this);
  if (!server) return server.error();
  server_ = std::move(server.value());
  return base::Ok{};
}

void Emulator::boot(bool to_bootloader) {
  if (server_) server_->detach();  // re-enumeration
  out_queue_.clear();
  in_queue_.clear();
  board_.drive_permille = {0, 0};
  board_.bootloader_requested = false;
  if (to_bootloader || boot0_) {
    mode_ = BoardMode::kBootloader;
    bootloader_.reset();
    return;
  }
  if (!flash_.application_valid()) {
    mode_ = BoardMode::kNoFirmware;  // the ROM jumps into garbage: nothing enumerates
    return;
  }
  // The emulator runs this firmware core for any image that says what it is; an image without
  // a valid info block is not one it can run: the board stays in the ROM bootloader, reachable
  // for a good image (as a bootloader that checks the image before starting it).
  const std::optional<cbx_image_info> image = flash_.image_info();
  if (!image) {
    mode_ = BoardMode::kBootloader;
    bootloader_.reset();
    return;
  }
  mode_ = BoardMode::kApplication;
  cbx_core_config config{};
  config.fw_version[0] = image->fw_major;
  config.fw_version[1] = image->fw_minor;
  config.fw_version[2] = image->fw_patch;
  std::snprintf(config.build, sizeof config.build, "%s", image->build);
  std::snprintf(config.serial, sizeof config.serial, "%s", options_.serial.c_str());
  std::snprintf(config.board, sizeof config.board, "cathbox-emu");
  for (int a = 0; a < 2; ++a) {
    config.axis[a].encoder_source = CBX_ENCODER_EDGES;
    config.axis[a].counter_bits = 32;
    config.axis[a].actuator = options_.motor ? CBX_ACTUATOR_MOTOR : CBX_ACTUATOR_BRAKE;
    config.axis[a].encoder_cpr = 4096;
  }
  edge_phase_ = {static_cast<uint8_t>(model_.state(0).count & 3), static_cast<uint8_t>(model_.state(1).count & 3)};
  SimBoard::Current current(board_);
  cbx_core_init(&core_->c, &config);
  // The core starts from count 0: feed it the lines' present phase without counting.
  for (int a = 0; a < 2; ++a) {
    cbx_core_encoder_rest(&core_->c, static_cast<cbx_axis>(a), kQuadrature[edge_phase_[static_cast<size_t>(a)]]);
  }
}

void Emulator::reset() { boot(false); }

void Emulator::unplug(uint64_t duration_us) {
  unplugged_until_us_ = now_us_ + duration_us;
  if (server_) server_->detach();
}

bool Emulator::attached(uint16_t& vid, uint16_t& pid) {
  if (now_us_ < unplugged_until_us_) return false;
  switch (mode_) {
    case BoardMode::kApplication: vid = CBX_USB_VID; pid = CBX_USB_PID; return true;
    case BoardMode::kBootloader: vid = CBX_DFU_VID; pid = CBX_DFU_PID; return true;
    case BoardMode::kNoFirmware: return false;
  }
  return false;
}

void Emulator::edge(int axis, int direction) {
  auto& phase = edge_phase_[static_cast<size_t>(axis)];
  phase = static_cast<uint8_t>((phase + (direction > 0 ? 1 : 3)) & 3u);
  cbx_core_encoder_edge(&core_->c, static_cast<cbx_axis>(axis), kQuadrature[phase]);
  ++edges_fed_;
}

void Emulator::feed_edges(int axis, int64_t steps) {
  const int direction = steps > 0 ? 1 : -1;
  auto& phase = edge_phase_[static_cast<size_t>(axis)];
  for (int64_t i = 0; i < std::llabs(steps); ++i) {
    bool bounced = false;
    if (faults_.chance(faults_.encoder.bounce)) {
      bounced = true;
      // One line chatters: it toggles and returns before the real edge.
      const uint8_t ab = kQuadrature[phase];
      const uint8_t line = faults_.uniform(2) == 0 ? 0b01 : 0b10;
      cbx_core_encoder_edge(&core_->c, static_cast<cbx_axis>(axis), static_cast<uint8_t>(ab ^ line));
      cbx_core_encoder_edge(&core_->c, static_cast<cbx_axis>(axis), ab);
      edges_fed_ += 2;
      ++faults_.mutable_counts().bounces;
    }
    if (!bounced && i + 1 < std::llabs(steps) && faults_.chance(faults_.encoder.skip)) {
      // The sample between two edges of a run is missed: both lines change at once. (Not
      // right after a bounce: the decoder takes the direction of its last transition, which
      // a bounce reverses; see hw-sim/README.md.)
      phase = static_cast<uint8_t>((phase + 2u) & 3u);
      cbx_core_encoder_edge(&core_->c, static_cast<cbx_axis>(axis), kQuadrature[phase]);
      edges_fed_ += 2;
      ++faults_.mutable_counts().skips;
      ++i;
      continue;
    }
    edge(axis, direction);
  }
}

void Emulator::physics_step() {
  std::array<int16_t, 2> drive = mode_ == BoardMode::kApplication ? board_.drive_permille : std::array<int16_t, 2>{0, 0};
  if (board_.estop_pressed) drive = {0, 0};  // the E-stop loop also cuts actuator power
  std::array<int64_t, 2> steps{};
  model_.step(kPhysicsStep_us * 1e-6, now_us_, drive, steps);
  for (int a = 0; a < 2; ++a) {
    const auto i = static_cast<size_t>(a);
    board_.current_mA[i] = static_cast<int16_t>(model_.current_mA(a, drive[i]));
    if (mode_ == BoardMode::kApplication && steps[i] != 0) feed_edges(a, steps[i]);
  }
}

void Emulator::advance(uint64_t us) {
  SimBoard::Current current(board_);
  const uint64_t end = now_us_ + us;
  while (now_us_ < end) {
    now_us_ += kPhysicsStep_us;
    board_.time_us = now_us_;
    physics_step();
    if (now_us_ % kTick_us == 0 && mode_ == BoardMode::kApplication) cbx_core_control_tick(&core_->c);
    if (now_us_ % kFrame_us == 0) usb_frame();
  }
}

void Emulator::service() {
  SimBoard::Current current(board_);
  if (server_) server_->poll();
  transitions();
}

void Emulator::usb_frame() {
  if (server_) server_->poll();  // OUT reports and control requests of this frame
  transitions();
  while (!out_queue_.empty() && out_queue_.front().due_us <= now_us_) {
    deliver_out(out_queue_.front().report);
    out_queue_.pop_front();
  }
  if (mode_ != BoardMode::kApplication) return;
  cbx_core_background(&core_->c);
  std::array<uint8_t, 64> report{};
  if (cbx_core_usb_in_report(&core_->c, report.data())) send_in(report);
  while (!in_queue_.empty() && in_queue_.front().due_us <= now_us_) {
    if (server_) server_->send_in(in_queue_.front().report);
    ++in_reports_;
    in_queue_.pop_front();
  }
}

void Emulator::rewrite_version(std::span<uint8_t> report) const { rewrite_wire_version(report, wire_version_); }

void Emulator::send_in(std::array<uint8_t, 64> report) {
  rewrite_version(report);
  const auto d = faults_.apply(faults_.in, report);
  for (int i = 0; i < d.copies; ++i) {
    if (d.delay_us > 0) {
      in_queue_.push_back({now_us_ + d.delay_us, report});
      continue;
    }
    if (now_us_ >= unplugged_until_us_ && server_) server_->send_in(report);
    ++in_reports_;
  }
}

void Emulator::on_out(std::span<const uint8_t> data) {
  if (mode_ != BoardMode::kApplication || data.size() != 64) return;
  std::array<uint8_t, 64> report{};
  std::copy(data.begin(), data.end(), report.begin());
  const auto d = faults_.apply(faults_.out, report);
  for (int i = 0; i < d.copies; ++i) {
    if (d.delay_us > 0) {
      out_queue_.push_back({now_us_ + d.delay_us, report});
    } else {
      deliver_out(report);
    }
  }
}

void Emulator::deliver_out(const std::array<uint8_t, 64>& report) {
  if (mode_ != BoardMode::kApplication) return;
  (void)cbx_core_usb_out_report(&core_->c, report.data(), report.size());
  ++out_delivered_;
}

bool Emulator::on_control(const cbx_usb_setup& setup, std::span<const uint8_t> data, std::vector<uint8_t>& reply) {
  reply.clear();
  bool ok = false;
  if (mode_ == BoardMode::kBootloader) {
    ok = bootloader_.control(setup, data, now_us_, reply);
  } else if (mode_ == BoardMode::kApplication) {
    const uint8_t type = static_cast<uint8_t>(setup.value >> 8);
    const uint8_t id = static_cast<uint8_t>(setup.value & 0xFFu);
    if (setup.request_type == CBX_USB_HID_GET_TYPE && setup.request == CBX_USB_HID_GET_REPORT &&
        type == CBX_USB_HID_REPORT_FEATURE && setup.length >= CBX_REPORT_SIZE) {
      reply.resize(CBX_REPORT_SIZE);
      ok = cbx_core_usb_feature_get(&core_->c, id, reply.data()) == CBX_OK;
      if (ok) rewrite_version(reply);
      if (!ok) reply.clear();
    } else if (setup.request_type == CBX_USB_HID_SET_TYPE && setup.request == CBX_USB_HID_SET_REPORT &&
               type == CBX_USB_HID_REPORT_FEATURE && (data.empty() || data[0] == id)) {
      ok = cbx_core_usb_feature_set(&core_->c, data.data(), data.size()) == CBX_OK;
    }
  }
  return ok;
}

void Emulator::transitions() {
  // Runs after the server has sent its replies: the board detaches and re-enumerates.
  if (mode_ == BoardMode::kApplication && board_.bootloader_requested) {
    boot(true);  // the firmware jumped into the ROM bootloader
  } else if (mode_ == BoardMode::kBootloader && bootloader_.leave_requested()) {
    boot(false);  // the ROM left DFU: reset into the application (if one is there)
  }
}

cbx_state_report Emulator::core_state() {
  cbx_state_report s{};
  SimBoard::Current current(board_);
  if (mode_ == BoardMode::kApplication) cbx_core_state(&core_->c, &s);
  return s;
}

}  // namespace cathbox::emu
