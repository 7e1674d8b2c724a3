#pragma once
// Times on the API: ISO 8601 in UTC with microseconds ("2024-11-24T17:31:05.123456Z").
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace cathbox::server {

[[nodiscard]] std::string iso_time(std::int64_t us_since_epoch);
// Accepts "YYYY-MM-DD", "YYYY-MM-DDTHH:MM:SS[.ffffff]Z" (also with a space for T).
[[nodiscard]] std::optional<std::int64_t> parse_iso_time(std::string_view text);

}  // namespace cathbox::server
