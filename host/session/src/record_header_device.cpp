#include "record_header_device.hpp"

namespace cathbox::session::record {
namespace {

int decode_device_field(std::uint64_t dt, std::span<const std::uint8_t> dv, std::size_t dat, DeviceRecord& d, FieldError& err) {
  using record::DeviceTag;
  switch (static_cast<DeviceTag>(dt)) {
    case DeviceTag::kDescription: d.description = text_of(dv); return 1;
    case DeviceTag::kSerial: d.serial = text_of(dv); return 1;
    case DeviceTag::kBoard: d.board = text_of(dv); return 1;
    case DeviceTag::kFirmware: d.firmware = text_of(dv); return 1;
    default: break;
  }
  if (dt < t(DeviceTag::kInsertionCountsPerM) || dt > t(DeviceTag::kRotationActuator)) return 0;
  std::uint64_t n = 0;
  if (!get_u64(dv, n) || n > UINT32_MAX) return err.bad(dat, "device: field " + std::to_string(dt) + " out of range");
  const auto v32 = static_cast<std::uint32_t>(n);
  switch (static_cast<DeviceTag>(dt)) {
    case DeviceTag::kInsertionCountsPerM: d.insertion_counts_per_m = v32; break;
    case DeviceTag::kRotationCountsPerRev: d.rotation_counts_per_rev = v32; break;
    case DeviceTag::kInsertionFullScaleMn: d.insertion_full_scale_mN = v32; break;
    case DeviceTag::kRotationFullScaleUnm: d.rotation_full_scale_uNm = v32; break;
    case DeviceTag::kInsertionActuator: d.insertion_actuator = static_cast<std::uint8_t>(v32); break;
    default: d.rotation_actuator = static_cast<std::uint8_t>(v32); break;
  }
  return 1;
}

}  // namespace

std::vector<std::uint8_t> encode_device(const DeviceRecord& d) {
  std::vector<std::uint8_t> out;
  ByteWriter w(out);
  using record::DeviceTag;
  w.field_text(t(DeviceTag::kDescription), d.description);
  w.field_text(t(DeviceTag::kSerial), d.serial);
  w.field_text(t(DeviceTag::kBoard), d.board);
  w.field_text(t(DeviceTag::kFirmware), d.firmware);
  w.field_u64(t(DeviceTag::kInsertionCountsPerM), d.insertion_counts_per_m);
  w.field_u64(t(DeviceTag::kRotationCountsPerRev), d.rotation_counts_per_rev);
  w.field_u64(t(DeviceTag::kInsertionFullScaleMn), d.insertion_full_scale_mN);
  w.field_u64(t(DeviceTag::kRotationFullScaleUnm), d.rotation_full_scale_uNm);
  w.field_u64(t(DeviceTag::kInsertionActuator), d.insertion_actuator);
  w.field_u64(t(DeviceTag::kRotationActuator), d.rotation_actuator);
  return out;
}

int decode_device(std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, FieldError& err) {
  DeviceRecord d;
  Fields f(v, at);
  const bool ok = f.each("device", [&](std::uint64_t dt, std::span<const std::uint8_t> dv, std::size_t dat) {
    return decode_device_field(dt, dv, dat, d, err);
  });
  if (!ok) return err.nested(f);
  h.device = std::move(d);
  return 1;
}

}  // namespace cathbox::session::record
