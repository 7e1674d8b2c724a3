#include "session/box_hand.hpp"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <thread>

#include "device/box_opener.hpp"
#include "device/force_law_command.hpp"

namespace cathbox::session {

base::Result<std::unique_ptr<BoxHand>> BoxHand::connect(const BoxHandOptions& options) {
  std::unique_ptr<BoxHand> hand(new BoxHand());
  hand->keyboard_ = options.keyboard;
  hand->dt_s_ = options.dt_s;
  hand->tool_ = options.tool;
  if (options.source == BoxSource::kSerial) {
    auto real = device::BoxClient::connect(device::box_opener_by_serial(options.serial), hand->clock_);
    if (!real) return base::Error{real.error().message};
    hand->client_ = std::move(real.value());
    hand->kind_ = "box";
  } else if (options.source == BoxSource::kAuto) {
    auto real = device::BoxClient::connect(device::box_opener(std::nullopt, hand->clock_), hand->clock_);
    if (real) {
      hand->client_ = std::move(real.value());
      hand->kind_ = "box";
    }
  }
  if (!hand->client_) {
    std::string socket = options.emu_socket;
    if (socket.empty()) {
      static int counter = 0;
      socket = "/tmp/cathbox-session-" + std::to_string(getpid()) + "-" + std::to_string(counter++) + ".sock";
      base::Result<std::unique_ptr<EmulatorProcess>> emulator =
          EmulatorProcess::start(options.emu_program, socket, options.emu_args);
      if (!emulator) return emulator.error();
      hand->emulator_ = std::move(*emulator);
    }
    // A starting emulator needs a moment to bind its socket: retry for up to 3 s.
    std::string last;
    for (int attempt = 0; attempt < 60 && !hand->client_; ++attempt) {
      auto c = device::BoxClient::connect(device::box_opener(socket, hand->clock_), hand->clock_);
      if (c) {
        hand->client_ = std::move(c.value());
      } else {
        last = c.error().message;
        if (!hand->emulator_ || !hand->emulator_->running()) break;
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
      }
    }
    if (!hand->client_) return base::Error{"emulated box at " + socket + ": " + last};
    hand->kind_ = hand->emulator_ ? "emulated box (started)" : "emulated box";
  }
  if (base::Status<> ready = hand->init(); !ready) return ready.error();
  return hand;
}

base::Result<std::unique_ptr<BoxHand>> BoxHand::attach(std::unique_ptr<device::BoxClient> client,
                                                       const BoxHandOptions& options) {
  std::unique_ptr<BoxHand> hand(new BoxHand());
  hand->client_ = std::move(client);
  hand->keyboard_ = options.keyboard;
  hand->dt_s_ = options.dt_s;
  hand->tool_ = options.tool;
  hand->kind_ = "box";
  if (base::Status<> ready = hand->init(); !ready) return ready.error();
  return hand;
}

base::Status<> BoxHand::init() {
  auto cal = client_->calibration();
  if (!cal) return base::Error{cal.error().message};
  calibration_ = cal.value();
  const EncoderCalibration encoders{calibration_.insertion_counts_per_m, calibration_.rotation_counts_per_rev};
  if (!encoders.valid()) return base::Error{client_->describe() + " is not calibrated (run 'cathbox calibrate')"};
  mapping_ = HandMapping(encoders);
  const cbx_device_info& info = client_->device_info();
  mode_ = info.insertion_actuator == CBX_ACTUATOR_MOTOR ? CBX_MODE_MOTOR : CBX_MODE_BRAKE;
  // The box's full scale and slew limit, which the law it is sent respects (passive_law.hpp).
  auto limits = client_->limits();
  if (!limits) return base::Error{limits.error().message};
  PassiveLawLimits passive;
  passive.full_scale_mN = std::min<double>(limits.value().max_force_mN, calibration_.insertion_full_scale_mN);
  passive.slew_mN_per_ms = limits.value().force_slew_mN_per_ms;
  passive.tick_ms = dt_s_ * 1e3;
  passive_ = PassiveLaw(passive);
  return base::Ok{};
}

BoxHand::~BoxHand() {
  if (client_) release();
  client_.reset();  // before the emulator goes
}

std::string BoxHand::describe() const { return kind_ + ": " + client_->describe(); }

std::optional<DeviceRecord> BoxHand::device() const {
  const cbx_device_info& info = client_->device_info();
  DeviceRecord d;
  d.description = describe();
  d.serial.assign(info.serial, strnlen(info.serial, sizeof info.serial));
  d.board.assign(info.board, strnlen(info.board, sizeof info.board));
  char fw[32];
  std::snprintf(fw, sizeof fw, "%u.%u.%u", info.fw_major, info.fw_minor, info.fw_patch);
  d.firmware = fw;
  d.insertion_counts_per_m = calibration_.insertion_counts_per_m;
  d.rotation_counts_per_rev = calibration_.rotation_counts_per_rev;
  d.insertion_full_scale_mN = calibration_.insertion_full_scale_mN;
  d.rotation_full_scale_uNm = calibration_.rotation_full_scale_uNm;
  d.insertion_actuator = info.insertion_actuator;
  d.rotation_actuator = info.rotation_actuator;
  return d;
}

void BoxHand::hold(std::size_t tool, const ToolCommand& at) {
  if (!tool_) mapping_.hold(tool, at);  // a bound box keeps its tool whichever one is held
}

void BoxHand::restart(std::size_t tool, const ToolCommand& at) {
  if (tool_.value_or(mapping_.held()) == tool) mapping_.hold(tool, at);
}

void BoxHand::read(std::int64_t, TickInput& in) {
  const bool fresh = client_->poll(state_);
  const cbx_state_report& s = state_.report;
  if (fresh && !mapping_.has_count_origin()) mapping_.set_count_origin({s.insertion_count, s.rotation_count});
  const HandPosition hand = mapping_.hand_from_counts({s.insertion_count, s.rotation_count});
  const std::size_t tool = tool_.value_or(in.held);
  if (tool >= in.tool_count) {
    in.box = status();
    return;  // bound to a tool the case does not have: checked by MultiBoxHand, never driven
  }
  if (tool_ && !bound_started_) {
    mapping_.hold(tool, in.tools[tool]);  // carry on from where the tool is
    bound_started_ = true;
  }
  // The keyboard moves the held tool, so only the box that drives it takes the keys.
  if (keyboard_ != nullptr && tool == in.held) {
    const KeyboardInput::Motion m = keyboard_->take(dt_s_);
    mapping_.nudge(m.insertion_um, m.rotation_urad, in.max_insertion_um[tool]);
  }
  in.tools[tool] = mapping_.command(hand);
  in.box = status();
}

BoxStatus BoxHand::status() const {
  return {true, client_->link() == device::Link::kUp, state_.report.faults};
}

void BoxHand::feel(const HandFeedback& fb) {
  if (fb.tick < 0) return;
  if (tool_ && *tool_ >= fb.tool_count) return;
  const tool::ForceLaw& law = tool_ ? fb.laws[*tool_] : fb.law;
  const cbx_state_report& s = state_.report;
  BoxReadback readback;
  readback.force_mN = s.insertion_force_mN;
  readback.speed_mm_s = mapping_.insertion_mm_from_counts(static_cast<double>(s.insertion_vel_cps));
  const ShapedLaw shaped = passive_.shape(mapping_.law_to_box(law), readback);
  (void)client_->send(device::force_law_command(shaped.law, mode_, shaped.out_min_mN, shaped.out_max_mN));
}

void BoxHand::release() {
  (void)client_->send(device::outputs_off_command());
  passive_.reset();
}

}  // namespace cathbox::session
