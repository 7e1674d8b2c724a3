#pragma once
// One interface for every way to reach a box: hidapi (a real box over hidraw) or the emulator
// socket. Nothing above it knows which one it has. The interrupt calls are non-blocking and
// allocation-free (a 1 kHz haptic thread calls them); feature calls block up to a timeout.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "device/result.hpp"

namespace cathbox::device {

inline constexpr size_t kReportSize = 64;  // report ID + 63-byte payload (protocol v1)
using Report = std::array<uint8_t, kReportSize>;

enum class IoStatus {
  kOk,            // one report moved
  kEmpty,         // nothing pending (read) / queue full, report dropped (write)
  kDisconnected,  // the device is gone; the transport must be reopened
};

class Transport {
 public:
  virtual ~Transport() = default;
  // Next pending interrupt IN report, without blocking.
  [[nodiscard]] virtual IoStatus read_in(Report& report) = 0;
  // Queues one interrupt OUT report, without blocking.
  [[nodiscard]] virtual IoStatus write_out(const Report& report) = 0;
  // GET_REPORT(feature): report[0] = id on return; blocks up to the transport's timeout.
  [[nodiscard]] virtual Status get_feature(uint8_t id, Report& report) = 0;
  // SET_REPORT(feature) with report[0] = id.
  [[nodiscard]] virtual Status set_feature(const Report& report) = 0;
  // Where this transport is connected, for messages ("hidraw 1209:cb01 /dev/hidraw3").
  [[nodiscard]] virtual std::string describe() const = 0;
};

}  // namespace cathbox::device
