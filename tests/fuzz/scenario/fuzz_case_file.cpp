// libFuzzer target: the case file parser never crashes, hangs or allocates without bound.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "scenario/case_file.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const cathbox::tool::CaseParse p = cathbox::tool::parse_case(text, "fuzz.case");
  if (!p && p.error().message.empty()) __builtin_trap();  // every failure names its cause
  return 0;
}
