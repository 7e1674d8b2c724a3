// libFuzzer target for one protocol decoder, chosen at compile time (CBX_FUZZ_KIND): a report
// kind, or the firmware image info block.
// Properties: never crash; a report that decodes
//   - re-encodes to the same bytes as the input on every byte that is not reserved (the spec's
//     reserved bytes are sent as 0 and ignored on receipt), so no field is dropped or moved;
//   - decodes again to a value equal to the first, field by field;
//   - re-encodes to the same bytes a second time.
#include <cstdint>
#include <cstdlib>
#include <cstring>

#include "../fuzz_crc_fix.hpp"
#include "protocol/cbx_command_report.h"
#include "protocol/cbx_feature_reports.h"
#include "protocol/cbx_image_info.h"
#include "protocol/cbx_state_report.h"

#define CBX_CAT2(a, b) a##b
#define CBX_CAT(a, b) CBX_CAT2(a, b)
#define CBX_DECODE CBX_CAT(CBX_CAT(cbx_, CBX_FUZZ_KIND), _decode)
#define CBX_ENCODE CBX_CAT(CBX_CAT(cbx_, CBX_FUZZ_KIND), _encode)

namespace {

// The bytes not carried from the input (the spec's reserved bytes, and a report's CRC, which
// covers them), as a mask: bit i = byte i (protocol/README.md).
constexpr uint64_t bytes(int first, int last) {
  uint64_t m = 0;
  for (int i = first; i <= last; ++i) m |= uint64_t{1} << i;
  return m;
}
constexpr uint64_t kCrc = bytes(62, 63);
[[maybe_unused]] uint64_t reserved(const cbx_state_report*) { return bytes(50, 61) | kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_command_report*) { return bytes(10, 11) | bytes(60, 61) | kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_device_info*) { return kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_calibration*) { return bytes(56, 61) | kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_limits*) { return bytes(26, 61) | kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_reset_counters*) { return bytes(9, 61) | kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_enter_bootloader*) { return bytes(12, 61) | kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_selftest*) { return bytes(9, 9) | bytes(18, 61) | kCrc; }
[[maybe_unused]] uint64_t reserved(const cbx_image_info*) { return bytes(10, 11) | bytes(36, 59); }

bool same(const cbx_header& a, const cbx_header& b) {
  return a.version == b.version && a.seq == b.seq && a.time_us == b.time_us;
}
bool same(const cbx_force_law& a, const cbx_force_law& b) {
  return a.offset == b.offset && a.pos0 == b.pos0 && a.stiffness == b.stiffness && a.damping == b.damping &&
         a.out_min == b.out_min && a.out_max == b.out_max;
}
bool same(const cbx_curve_point (&a)[CBX_CURVE_POINTS], const cbx_curve_point (&b)[CBX_CURVE_POINTS]) {
  for (unsigned i = 0; i < CBX_CURVE_POINTS; ++i)
    if (a[i].in_permille != b[i].in_permille || a[i].out_permille != b[i].out_permille) return false;
  return true;
}
[[maybe_unused]] bool same(const cbx_state_report& a, const cbx_state_report& b) {
  return same(a.header, b.header) && a.insertion_count == b.insertion_count && a.rotation_count == b.rotation_count &&
         a.insertion_vel_cps == b.insertion_vel_cps && a.rotation_vel_cps == b.rotation_vel_cps &&
         a.insertion_force_mN == b.insertion_force_mN && a.rotation_torque_uNm == b.rotation_torque_uNm &&
         a.insertion_current_mA == b.insertion_current_mA && a.rotation_current_mA == b.rotation_current_mA &&
         a.status == b.status && a.faults == b.faults && a.command_seq_echo == b.command_seq_echo &&
         a.encoder_errors == b.encoder_errors && a.rx_errors == b.rx_errors && a.mode == b.mode &&
         a.board_faults == b.board_faults && a.in_dropped == b.in_dropped;
}
[[maybe_unused]] bool same(const cbx_command_report& a, const cbx_command_report& b) {
  return same(a.header, b.header) && a.mode == b.mode && a.flags == b.flags && same(a.insertion, b.insertion) &&
         same(a.rotation, b.rotation);
}
[[maybe_unused]] bool same(const cbx_device_info& a, const cbx_device_info& b) {
  return same(a.header, b.header) && a.fw_major == b.fw_major && a.fw_minor == b.fw_minor &&
         a.fw_patch == b.fw_patch && a.protocol_minor == b.protocol_minor &&
         std::memcmp(a.serial, b.serial, sizeof a.serial) == 0 && std::memcmp(a.board, b.board, sizeof a.board) == 0 &&
         a.insertion_actuator == b.insertion_actuator && a.rotation_actuator == b.rotation_actuator &&
         a.insertion_encoder_cpr == b.insertion_encoder_cpr && a.rotation_encoder_cpr == b.rotation_encoder_cpr &&
         std::memcmp(a.build, b.build, sizeof a.build) == 0;
}
[[maybe_unused]] bool same(const cbx_calibration& a, const cbx_calibration& b) {
  return same(a.header, b.header) && a.insertion_counts_per_m == b.insertion_counts_per_m &&
         a.rotation_counts_per_rev == b.rotation_counts_per_rev &&
         a.insertion_full_scale_mN == b.insertion_full_scale_mN &&
         a.rotation_full_scale_uNm == b.rotation_full_scale_uNm && same(a.insertion_curve, b.insertion_curve) &&
         same(a.rotation_curve, b.rotation_curve);
}
[[maybe_unused]] bool same(const cbx_limits& a, const cbx_limits& b) {
  return same(a.header, b.header) && a.max_force_mN == b.max_force_mN && a.max_torque_uNm == b.max_torque_uNm &&
         a.watchdog_timeout_ms == b.watchdog_timeout_ms &&
         a.insertion_max_current_mA == b.insertion_max_current_mA &&
         a.rotation_max_current_mA == b.rotation_max_current_mA &&
         a.force_slew_mN_per_ms == b.force_slew_mN_per_ms && a.torque_slew_uNm_per_ms == b.torque_slew_uNm_per_ms;
}
[[maybe_unused]] bool same(const cbx_reset_counters& a, const cbx_reset_counters& b) { return same(a.header, b.header) && a.mask == b.mask; }
[[maybe_unused]] bool same(const cbx_enter_bootloader& a, const cbx_enter_bootloader& b) {
  return same(a.header, b.header) && a.magic == b.magic;
}
[[maybe_unused]] bool same(const cbx_image_info& a, const cbx_image_info& b) {
  return a.fw_major == b.fw_major && a.fw_minor == b.fw_minor && a.fw_patch == b.fw_patch &&
         a.protocol_minor == b.protocol_minor && std::memcmp(a.board, b.board, sizeof a.board) == 0 &&
         std::memcmp(a.build, b.build, sizeof a.build) == 0 && a.image_size == b.image_size;
}
[[maybe_unused]] bool same(const cbx_selftest& a, const cbx_selftest& b) {
  return same(a.header, b.header) && a.state == b.state && a.failed_checks == b.failed_checks &&
         a.insertion_current_mA == b.insertion_current_mA && a.rotation_current_mA == b.rotation_current_mA &&
         a.supply_mV == b.supply_mV;
}

// Every byte of the 64 that is not in `reserved_bytes` is equal in `a` and `b`.
bool payload_carried(const uint8_t* a, const uint8_t* b, uint64_t reserved_bytes) {
  for (unsigned i = 0; i < CBX_REPORT_SIZE; ++i)
    if (((reserved_bytes >> i) & 1u) == 0u && a[i] != b[i]) return false;
  return true;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* input, size_t size) {
  uint8_t fixed[CBX_REPORT_SIZE];
  const uint8_t* data = cbx_fuzz_fix_crc(input, size, fixed);
  CBX_FUZZ_TYPE first;
  if (CBX_DECODE(data, size, &first) != CBX_OK) return 0;
  uint8_t once[CBX_REPORT_SIZE];
  if (CBX_ENCODE(&first, once) != CBX_OK) std::abort();
  if (!payload_carried(data, once, reserved(&first))) std::abort();
  CBX_FUZZ_TYPE second;
  if (CBX_DECODE(once, sizeof once, &second) != CBX_OK) std::abort();
  if (!same(first, second)) std::abort();
  uint8_t twice[CBX_REPORT_SIZE];
  if (CBX_ENCODE(&second, twice) != CBX_OK) std::abort();
  if (std::memcmp(once, twice, sizeof once) != 0) std::abort();
  return 0;
}
