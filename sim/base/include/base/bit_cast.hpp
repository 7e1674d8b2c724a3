#pragma once
// std::bit_cast, or the compiler builtin it is made of where the library lacks it (libc++
// before 14's full <bit>: emscripten's, the WebAssembly build).
#include <version>

#if defined(__cpp_lib_bit_cast)
#include <bit>
#endif

namespace cathbox::base {

template <class To, class From>
  requires(sizeof(To) == sizeof(From))
[[nodiscard]] constexpr To bit_cast(const From& from) noexcept {
#if defined(__cpp_lib_bit_cast)
  return std::bit_cast<To>(from);
#else
  return __builtin_bit_cast(To, from);
#endif
}

}  // namespace cathbox::base
