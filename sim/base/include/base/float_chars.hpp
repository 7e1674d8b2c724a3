#pragma once
// std::to_chars for double (the shortest form), where the standard library has it; libc++
// before 20 (emscripten's, the WebAssembly build) has only the integer overloads, so there the
// text comes from snprintf in the "C" locale: the fewest %g digits that read back to the same
// double (round-trip exact like to_chars; fixed and scientific may be chosen differently).
#include <charconv>
#include <cstdio>
#include <cstdlib>
#include <system_error>

namespace cathbox::base {

#if defined(_LIBCPP_VERSION) && _LIBCPP_VERSION < 200000
namespace detail {
inline std::to_chars_result print_into(char* first, char* last, int digits, double value) {
  const int n = std::snprintf(first, static_cast<std::size_t>(last - first), "%.*g", digits, value);
  if (n < 0 || n >= last - first) return {last, std::errc::value_too_large};
  return {first + n, std::errc()};
}
}  // namespace detail

[[nodiscard]] inline std::to_chars_result double_chars(char* first, char* last, double value) {
  std::to_chars_result r{last, std::errc::value_too_large};
  for (int digits = 1; digits <= 17; ++digits) {
    r = detail::print_into(first, last, digits, value);
    if (r.ec != std::errc() || std::strtod(first, nullptr) == value) break;
  }
  return r;
}

#else
[[nodiscard]] inline std::to_chars_result double_chars(char* first, char* last, double value) {
  return std::to_chars(first, last, value);
}

#endif

}  // namespace cathbox::base
