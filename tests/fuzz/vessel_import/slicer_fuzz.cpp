// Fuzzes the Slicer markups reader (JSON by nlohmann-json, our tree and curve reading) and
// everything after it.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "fuzz_check.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  using namespace cathbox::vessel_import;
  fuzz::check(import_centerlines_text(text, "fuzz.mrk.json", Format::kSlicerMarkups));
  return 0;
}
