#pragma once
// What a record says about its run before the first tick: enough to rebuild the same session
// anywhere (the case file and its HCLM file verbatim, the tools as they were simulated, the
// entry), and who ran it on what (software version, start time, the hand, the box's device
// information and calibration). Encoded as tagged fields (record_format.hpp).
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "session/device_record.hpp"
#include "session/hand.hpp"
#include "tool/simulator.hpp"
#include "tool/tool_spec.hpp"

namespace cathbox::session {

struct RecordHeader {
  std::string software_version;
  std::int64_t start_unix_us = 0;
  std::string case_name;
  std::string case_file;    // the case file as opened (empty when a bare vessel file was)
  std::string case_text;    // its bytes
  std::string vessel_file;  // the HCLM file (empty for analytic tubes)
  std::string vessel_text;  // its bytes
  std::string surface_file;   // the case's own wall (`surface FILE`; empty: meshed from the HCLM)
  std::string surface_bytes;  // its bytes (CBXMESH2, scenario/case_surface.hpp)
  std::vector<tool::ToolSpec> tools;
  tool::Entry entry;
  std::size_t held_tool = 0;
  HandKind hand = HandKind::kKeyboard;
  std::string hand_description;
  std::optional<DeviceRecord> device;
  std::int64_t period_us = 1000;
  std::int64_t hash_every = 100;
};

[[nodiscard]] std::vector<std::uint8_t> encode_header(const RecordHeader& header);
// Decodes a header block's data; on failure returns false with what went wrong and the offset
// (in the block's data) where.
[[nodiscard]] bool decode_header(std::span<const std::uint8_t> data, RecordHeader& out, std::string& what,
                                 std::size_t& offset);

}  // namespace cathbox::session
