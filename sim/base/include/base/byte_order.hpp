#pragma once
// Little-endian fields in a byte buffer, for C++ code that reads or writes a file or wire
// format (the session record, ...). The same rules as protocol/include/protocol/cbx_bytes.h,
// which the C code (protocol, firmware, emulator) keeps: C++ modules that are not drivers read
// through this header and so do not depend on the protocol target.
#include <concepts>
#include <cstddef>
#include <cstdint>

namespace cathbox::base {

// Writes the low sizeof(T) bytes of v at p, least significant first.
template <std::unsigned_integral T>
constexpr void put_le(std::uint8_t* p, T v) {
  for (std::size_t i = 0; i < sizeof(T); ++i) p[i] = static_cast<std::uint8_t>(v >> (8 * i));
}

// Reads sizeof(T) bytes at p, least significant first.
template <std::unsigned_integral T>
[[nodiscard]] constexpr T get_le(const std::uint8_t* p) {
  T v = 0;
  for (std::size_t i = 0; i < sizeof(T); ++i) v = static_cast<T>(v | static_cast<T>(static_cast<T>(p[i]) << (8 * i)));
  return v;
}

}  // namespace cathbox::base
