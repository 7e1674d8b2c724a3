#include "device/box_client.hpp"

#include <cstdint>
#include <cstdio>

namespace cathbox::device {
namespace {

std::string status_line(const char* what, cbx_status status) {
  return std::string(what) + ": " + cbx_status_name(status);
}

}  // namespace

std::string BoxClient::incompatible_message(unsigned version) {
  return "the box speaks protocol v" + std::to_string(version) + ", this host speaks v" +
         std::to_string(CBX_PROTOCOL_VERSION) + ": update the host tools (or flash firmware " +
         std::to_string(CBX_PROTOCOL_VERSION) + ".x)";
}

BoxClient::BoxClient(Opener opener, Clock& clock, Options options)
    : opener_(std::move(opener)), clock_(clock), options_(options) {}

Result<std::unique_ptr<BoxClient>> BoxClient::connect(Opener opener, Clock& clock, Options options) {
  std::unique_ptr<BoxClient> client(new BoxClient(std::move(opener), clock, options));
  auto opened = client->open_link();
  if (!opened) return opened.error();
  return client;
}

Status BoxClient::open_link() {
  auto opened = opener_();
  if (!opened) return opened.error();
  transport_ = std::move(opened.value());
  auto info = read_device_info();
  if (!info) {
    transport_.reset();
    return info.error();
  }
  info_ = info.value();
  have_state_seq_ = false;  // a restarted box counts from anywhere
  return Ok{};
}

void BoxClient::drop_link() {
  if (!transport_) return;
  transport_.reset();
  ++stats_.disconnects;
  down_since_us_ = clock_.now_us();
  next_attempt_us_ = down_since_us_;
}

void BoxClient::try_reconnect() {
  const uint64_t now = clock_.now_us();
  if (now < next_attempt_us_) return;
  // A failed attempt (even one whose feature calls see the link drop again) is still the same
  // outage: its start, its count and the next attempt one interval on are kept.
  const uint64_t down_since = down_since_us_;
  const uint64_t disconnects = stats_.disconnects;
  const uint64_t next_attempt = now + options_.reconnect_interval_us;
  bool up = open_link().ok();
  // Restore what this session configured; a box that restarted has lost it (or kept it).
  if (up && session_limits_) up = set_limits(limits_).ok();
  if (up && session_calibration_) up = set_calibration(calibration_).ok();
  if (!up) {
    transport_.reset();
    stats_.disconnects = disconnects;
    down_since_us_ = down_since;
    next_attempt_us_ = next_attempt;
    return;
  }
  next_attempt_us_ = next_attempt;
  ++stats_.reconnects;
  stats_.last_reconnect_us = clock_.now_us() - down_since_us_;
  if (have_command_) (void)send(last_command_);
}

void BoxClient::count_rejected(cbx_status status) {
  switch (status) {
    case CBX_ERR_LENGTH: ++stats_.rejected_length; break;
    case CBX_ERR_REPORT_ID: ++stats_.rejected_id; break;
    case CBX_ERR_VERSION: ++stats_.rejected_version; break;
    case CBX_ERR_CRC: ++stats_.rejected_crc; break;
    default: ++stats_.rejected_range; break;
  }
}

bool BoxClient::poll(BoxState& state) {
  if (!transport_) {
    try_reconnect();
    if (!transport_) return false;
  }
  bool updated = false;
  // Drains everything queued (a socket or hidraw buffer holds at most a few hundred reports),
  // bounded so that a flood cannot hold the haptic thread.
  for (int i = 0; i < 4096; ++i) {
    const IoStatus io = transport_->read_in(rx_);
    if (io == IoStatus::kEmpty) break;
    if (io == IoStatus::kDisconnected) {
      drop_link();
      break;
    }
    cbx_state_report decoded;
    const cbx_status status = cbx_state_decode(rx_.data(), rx_.size(), &decoded);
    if (status != CBX_OK) {
      count_rejected(status);
      continue;
    }
    if (have_state_seq_) {
      const uint16_t delta = static_cast<uint16_t>(decoded.header.seq - last_state_seq_);
      if (delta == 0 || delta >= 0x8000u) {
        ++stats_.states_stale;
        continue;
      }
      stats_.states_missed += delta - 1u;
    }
    have_state_seq_ = true;
    last_state_seq_ = decoded.header.seq;
    if (updated) ++stats_.states_superseded;
    ++stats_.states_accepted;
    state.report = decoded;
    state.received_us = clock_.now_us();
    updated = true;
  }
  return updated;
}

bool BoxClient::send(const cbx_command_report& command) {
  last_command_ = command;
  have_command_ = true;
  if (!transport_) {
    ++stats_.commands_dropped;
    return false;
  }
  cbx_command_report out = command;
  out.header.version = CBX_PROTOCOL_VERSION;
  out.header.seq = command_seq_;
  out.header.time_us = static_cast<uint32_t>(clock_.now_us());
  if (cbx_command_encode(&out, tx_.data()) != CBX_OK) {
    ++stats_.commands_dropped;
    return false;
  }
  ++command_seq_;
  const IoStatus io = transport_->write_out(tx_);
  if (io == IoStatus::kOk) {
    ++stats_.commands_sent;
    return true;
  }
  ++stats_.commands_dropped;
  if (io == IoStatus::kDisconnected) drop_link();
  return false;
}

std::string BoxClient::describe() const {
  return transport_ ? transport_->describe() : std::string("(link down, reconnecting)");
}

Status BoxClient::get_feature(uint8_t id, Report& report) {
  if (!transport_) return make_error(Errc::kDisconnected, "the box is not connected");
  auto got = transport_->get_feature(id, report);
  if (!got && got.error().code == Errc::kDisconnected) drop_link();
  return got;
}

Status BoxClient::set_feature(const Report& report) {
  if (!transport_) return make_error(Errc::kDisconnected, "the box is not connected");
  auto done = transport_->set_feature(report);
  if (!done && done.error().code == Errc::kDisconnected) drop_link();
  return done;
}

Result<cbx_device_info> BoxClient::read_device_info() {
  Report report{};
  auto got = get_feature(CBX_ID_DEVICE_INFO, report);
  if (!got) return got.error();
  cbx_device_info info;
  const cbx_status status = cbx_device_info_decode(report.data(), report.size(), &info);
  if (status == CBX_ERR_VERSION) return make_error(Errc::kIncompatible, incompatible_message(report[1]));
  if (status != CBX_OK) return make_error(Errc::kBadReport, status_line("device info report (0x10)", status));
  return info;
}

template <class T>
Result<T> BoxClient::get_typed(uint8_t id, cbx_status (*decode)(const uint8_t*, size_t, T*)) {
  Report report{};
  auto got = get_feature(id, report);
  if (!got) return got.error();
  T value;
  const cbx_status status = decode(report.data(), report.size(), &value);
  if (status != CBX_OK) {
    char what[40];
    std::snprintf(what, sizeof what, "feature report 0x%02x", id);
    return make_error(status == CBX_ERR_VERSION ? Errc::kIncompatible : Errc::kBadReport, status_line(what, status));
  }
  return value;
}

template <class T>
Status BoxClient::set_typed(uint8_t id, const T& value, cbx_status (*encode)(const T*, uint8_t*)) {
  T out = value;
  out.header.version = CBX_PROTOCOL_VERSION;
  out.header.seq = feature_seq_++;
  out.header.time_us = static_cast<uint32_t>(clock_.now_us());
  Report report{};
  const cbx_status status = encode(&out, report.data());
  if (status != CBX_OK) {
    char what[48];
    std::snprintf(what, sizeof what, "refusing to send feature report 0x%02x", id);
    return make_error(Errc::kBadArgument, status_line(what, status));
  }
  return set_feature(report);
}

Result<cbx_calibration> BoxClient::calibration() { return get_typed<cbx_calibration>(CBX_ID_CALIBRATION, cbx_calibration_decode); }

Status BoxClient::set_calibration(const cbx_calibration& calibration) {
  auto done = set_typed<cbx_calibration>(CBX_ID_CALIBRATION, calibration, cbx_calibration_encode);
  if (done) {
    calibration_ = calibration;
    session_calibration_ = true;
  }
  return done;
}

Result<cbx_limits> BoxClient::limits() { return get_typed<cbx_limits>(CBX_ID_LIMITS, cbx_limits_decode); }

Status BoxClient::set_limits(const cbx_limits& limits) {
  auto done = set_typed<cbx_limits>(CBX_ID_LIMITS, limits, cbx_limits_encode);
  if (done) {
    limits_ = limits;
    session_limits_ = true;
  }
  return done;
}

Status BoxClient::reset_counters(uint8_t mask) {
  cbx_reset_counters value{};
  value.mask = mask;
  return set_typed<cbx_reset_counters>(CBX_ID_RESET_COUNTERS, value, cbx_reset_counters_encode);
}

Status BoxClient::start_selftest() {
  cbx_selftest value{};
  value.state = CBX_SELFTEST_RUNNING;
  return set_typed<cbx_selftest>(CBX_ID_SELFTEST, value, cbx_selftest_encode);
}

Result<cbx_selftest> BoxClient::selftest() { return get_typed<cbx_selftest>(CBX_ID_SELFTEST, cbx_selftest_decode); }

Status BoxClient::enter_bootloader() {
  cbx_enter_bootloader value{};
  value.magic = CBX_BOOTLOADER_MAGIC;
  auto done = set_typed<cbx_enter_bootloader>(CBX_ID_ENTER_BOOTLOADER, value, cbx_enter_bootloader_encode);
  if (done) {
    transport_.reset();  // the box detaches; no reconnection attempts are counted as an outage
    down_since_us_ = clock_.now_us();
    next_attempt_us_ = UINT64_MAX;
  }
  return done;
}

}  // namespace cathbox::device
