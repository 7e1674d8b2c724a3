#pragma once
// Whitespace-separated text fields, as every text reader of the project splits its lines (HCLM,
// SWC, case files, action scripts): tokens, numbers in full (a token is a number only if all of
// it is), and the one way to show untrusted text in a one-line message (escape_bytes, quoted).
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace cathbox::base::text {

// Space, tab, CR, VT, FF (a line's end is the caller's).
[[nodiscard]] inline bool is_space(char ch) {
  return ch == ' ' || ch == '\t' || ch == '\r' || ch == '\v' || ch == '\f';
}

[[nodiscard]] inline std::string_view trim(std::string_view s) {
  while (!s.empty() && is_space(s.front())) s.remove_prefix(1);
  while (!s.empty() && is_space(s.back())) s.remove_suffix(1);
  return s;
}

// Appends the tokens of s to tokens (cleared first).
inline void split_tokens(std::string_view s, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && is_space(s[i])) ++i;
    const std::size_t start = i;
    while (i < s.size() && !is_space(s[i])) ++i;
    if (i > start) tokens.push_back(s.substr(start, i - start));
  }
}

[[nodiscard]] inline std::vector<std::string_view> split_tokens(std::string_view s) {
  std::vector<std::string_view> tokens;
  split_tokens(s, tokens);
  return tokens;
}

// The text as it may stand in a one-line message: bytes outside printable ASCII (controls,
// DEL, non-ASCII) as \xNN, cut after max_chars input bytes with "..." after.
[[nodiscard]] inline std::string escape_bytes(std::string_view text, std::size_t max_chars = std::string_view::npos) {
  std::string out;
  for (const char ch : text.substr(0, max_chars)) {
    const auto u = static_cast<unsigned char>(ch);
    if (u < 0x20 || u >= 0x7f) {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02x", u);
      out += buf;
    } else {
      out += ch;
    }
  }
  if (text.size() > max_chars) out += "...";
  return out;
}

// 'token', escaped and cut after 40 characters.
[[nodiscard]] inline std::string quoted(std::string_view token) { return "'" + escape_bytes(token, 40) + "'"; }

// The whole token as a number (a leading '+' allowed), else nullopt.
[[nodiscard]] inline std::optional<double> parse_double(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  double value = 0.0;
#if defined(_LIBCPP_VERSION) && _LIBCPP_VERSION < 200000
  // libc++ before 20 (emscripten's, the WebAssembly build) has no floating-point from_chars:
  // strtod (correctly rounded, the "C" locale there) on the same tokens from_chars takes, so
  // no leading space or second sign, no hexadecimal, nothing out of range.
  if (token.empty() || std::isspace(static_cast<unsigned char>(token.front())) != 0 || token.front() == '+' ||
      token.find_first_of("xX") != std::string_view::npos) {
    return std::nullopt;
  }
  const std::string text(token);
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  if (errno == ERANGE || end != text.c_str() + text.size()) return std::nullopt;
#else
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || ptr != token.data() + token.size()) return std::nullopt;
#endif
  return value;
}

// parse_double, and finite.
[[nodiscard]] inline std::optional<double> parse_number(std::string_view token) {
  const std::optional<double> v = parse_double(token);
  if (!v || !std::isfinite(*v)) return std::nullopt;
  return v;
}

[[nodiscard]] inline std::optional<std::int64_t> parse_integer(std::string_view token) {
  if (!token.empty() && token.front() == '+') token.remove_prefix(1);
  std::int64_t value = 0;
  const auto [ptr, ec] = std::from_chars(token.data(), token.data() + token.size(), value);
  if (ec != std::errc() || ptr != token.data() + token.size()) return std::nullopt;
  return value;
}

}  // namespace cathbox::base::text
