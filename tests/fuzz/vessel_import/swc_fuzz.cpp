// Fuzzes the SWC reader and everything after it (branches, network, radius filter, validation).
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  using namespace cathbox::vessel_import;
  fuzz::check(import_centerlines_text(text, "fuzz.swc", Format::kSwc));
  return 0;
}
