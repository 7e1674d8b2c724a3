#pragma once
// The box a run was made with, as its record keeps it (from the box's device-info and
// calibration feature reports).
#include <cstdint>
#include <string>

namespace cathbox::session {

struct DeviceRecord {
  std::string description;  // "emulator 1209:cb01 /tmp/...", "hidraw ..."
  std::string serial;
  std::string board;
  std::string firmware;     // "1.2.3"
  std::uint32_t insertion_counts_per_m = 0;
  std::uint32_t rotation_counts_per_rev = 0;
  std::uint32_t insertion_full_scale_mN = 0;
  std::uint32_t rotation_full_scale_uNm = 0;
  std::uint8_t insertion_actuator = 0;  // CBX_ACTUATOR_*
  std::uint8_t rotation_actuator = 0;
};

}  // namespace cathbox::session
