#pragma once
// BoxClient: the typed host API over protocol/ on any Transport. The per-tick calls (poll, send)
// are non-blocking and allocation-free while the link is up, so a 1 kHz haptic thread can call
// them; feature calls block (up to the transport's timeout) and belong outside the haptic loop.
// Not thread-safe: one thread uses a client.
//
// Reconnection: when the transport reports the device gone (unplugged, emulator restarted),
// poll() reopens it every Options::reconnect_interval_us, repeats the version check, restores
// the calibration and limits this session set, and resends the last command. The caller keeps
// its BoxClient, its command sequence numbers and its statistics.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "device/clock.hpp"
#include "device/result.hpp"
#include "device/transport.hpp"
#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_state_report.h"

namespace cathbox::device {

struct BoxState {
  cbx_state_report report{};  // the newest valid state
  uint64_t received_us = 0;   // host clock when it was read
};

// Counters of everything the client saw; never reset for the life of the client.
struct ClientStats {
  uint64_t states_accepted = 0;
  uint64_t states_superseded = 0;  // valid, but a newer one came in the same drain
  uint64_t states_missed = 0;      // sequence gaps (reports the box sent that never arrived)
  uint64_t states_stale = 0;       // duplicates or out-of-order (seq not newer): ignored
  uint64_t rejected_length = 0;    // malformed reports, by decoder status, never acted on
  uint64_t rejected_id = 0;
  uint64_t rejected_version = 0;
  uint64_t rejected_crc = 0;
  uint64_t rejected_range = 0;
  uint64_t commands_sent = 0;
  uint64_t commands_dropped = 0;  // the transport's queue was full or the link was down
  uint64_t disconnects = 0;
  uint64_t reconnects = 0;
  uint64_t last_reconnect_us = 0;  // time from losing the link to having it back, last time
  [[nodiscard]] uint64_t rejected() const {
    return rejected_length + rejected_id + rejected_version + rejected_crc + rejected_range;
  }
};

enum class Link { kUp, kDown };

class BoxClient {
 public:
  using Opener = std::function<Result<std::unique_ptr<Transport>>()>;
  struct Options {
    uint64_t reconnect_interval_us = 50'000;
  };

  // Opens the transport, reads the device info and checks the protocol version. An
  // incompatible box gives Errc::kIncompatible with the one-line message of protocol/README.md.
  [[nodiscard]] static Result<std::unique_ptr<BoxClient>> connect(Opener opener, Clock& clock, Options options);
  [[nodiscard]] static Result<std::unique_ptr<BoxClient>> connect(Opener opener, Clock& clock) {
    return connect(std::move(opener), clock, Options{});
  }

  // Drains every pending IN report and keeps the newest valid one in `state`. Returns true
  // when `state` was updated. While the link is down it tries to reconnect (see above).
  [[nodiscard]] bool poll(BoxState& state);
  // Sends one command; fills its header (version, seq, time). False when it was not queued.
  [[nodiscard]] bool send(const cbx_command_report& command);
  // The seq the next command will carry.
  [[nodiscard]] uint16_t next_command_seq() const { return command_seq_; }

  [[nodiscard]] Link link() const { return transport_ ? Link::kUp : Link::kDown; }
  [[nodiscard]] const ClientStats& stats() const { return stats_; }
  [[nodiscard]] const cbx_device_info& device_info() const { return info_; }
  [[nodiscard]] std::string describe() const;

  // Feature reports (blocking).
  [[nodiscard]] Result<cbx_device_info> read_device_info();
  [[nodiscard]] Result<cbx_calibration> calibration();
  [[nodiscard]] Status set_calibration(const cbx_calibration& calibration);
  [[nodiscard]] Result<cbx_limits> limits();
  [[nodiscard]] Status set_limits(const cbx_limits& limits);
  [[nodiscard]] Status reset_counters(uint8_t mask);
  [[nodiscard]] Status start_selftest();
  [[nodiscard]] Result<cbx_selftest> selftest();
  // Asks the box to reboot into the ROM DFU bootloader; the link goes down on success.
  [[nodiscard]] Status enter_bootloader();

  // The one-line message for a box that speaks protocol major `version`.
  [[nodiscard]] static std::string incompatible_message(unsigned version);

 private:
  BoxClient(Opener opener, Clock& clock, Options options);
  [[nodiscard]] Status open_link();
  void drop_link();
  void try_reconnect();
  void count_rejected(cbx_status status);
  [[nodiscard]] Status get_feature(uint8_t id, Report& report);
  [[nodiscard]] Status set_feature(const Report& report);
  template <class T>
  [[nodiscard]] Status set_typed(uint8_t id, const T& value, cbx_status (*encode)(const T*, uint8_t*));
  template <class T>
  [[nodiscard]] Result<T> get_typed(uint8_t id, cbx_status (*decode)(const uint8_t*, size_t, T*));

  Opener opener_;
  Clock& clock_;
  Options options_;
  std::unique_ptr<Transport> transport_;
  cbx_device_info info_{};
  ClientStats stats_{};
  Report rx_{};
  Report tx_{};
  uint16_t command_seq_ = 0;
  uint16_t feature_seq_ = 0;
  bool have_state_seq_ = false;
  uint16_t last_state_seq_ = 0;
  bool have_command_ = false;
  cbx_command_report last_command_{};
  bool session_calibration_ = false;
  cbx_calibration calibration_{};
  bool session_limits_ = false;
  cbx_limits limits_{};
  uint64_t down_since_us_ = 0;
  uint64_t next_attempt_us_ = 0;
};

}  // namespace cathbox::device
