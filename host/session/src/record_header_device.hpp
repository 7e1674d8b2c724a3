#pragma once
// The box's device information and calibration in the record header (record_header.hpp,
// device_record.hpp): nested tagged fields (record_format.hpp, DeviceTag).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "record_header_fields.hpp"
#include "session/record_header.hpp"

namespace cathbox::session::record {

[[nodiscard]] std::vector<std::uint8_t> encode_device(const DeviceRecord& d);
// The device field at `at` into h.device: 1, or -1 with `err` set.
int decode_device(std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, FieldError& err);

}  // namespace cathbox::session::record
