#pragma once
// Whitespace-separated text fields, as the HCLM and SWC readers split their lines: tokens,
// numbers in full (a token is a number only if all of it is), and tokens quoted for messages.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::vessel::text {

// Space, tab, CR, VT, FF.
[[nodiscard]] bool is_space(char ch);
[[nodiscard]] std::string_view trim(std::string_view s);
[[nodiscard]] std::vector<std::string_view> split_tokens(std::string_view s);
// 'token' with control and non-ASCII bytes as \xNN, cut after 40 characters.
[[nodiscard]] std::string quoted(std::string_view token);
// The whole token as a number (a leading '+' allowed), else nullopt.
[[nodiscard]] std::optional<double> parse_double(std::string_view token);
[[nodiscard]] std::optional<std::int64_t> parse_integer(std::string_view token);

}  // namespace cathbox::vessel::text
