#pragma once
// A tool in the record header (record_header.hpp): its ToolSpec as nested tagged fields
// (record_format.hpp, ToolTag).
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "record_header_fields.hpp"
#include "session/record_header.hpp"

namespace cathbox::session::record {

[[nodiscard]] std::vector<std::uint8_t> encode_tool(const tool::ToolSpec& spec);
// The tool field at `at` appended to h.tools: 1, or -1 with `err` set (more than kMaxTools, a bad field).
int decode_tool(std::span<const std::uint8_t> v, std::size_t at, RecordHeader& h, FieldError& err);

}  // namespace cathbox::session::record
