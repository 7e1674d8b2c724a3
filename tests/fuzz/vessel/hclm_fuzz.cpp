// Fuzzes read_hclm(): any byte string must give a model or diagnostics, never a crash. Valid
// inputs must survive write -> read unchanged, and small valid models must mesh or fail
// cleanly (an error string), never crash.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "vessel/hclm.hpp"
#include "vessel/vessel_mesher.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  const cathbox::vessel::HclmReadResult read = cathbox::vessel::read_hclm(text, "fuzz.hclm");
  if (!read.ok()) {
    if (read.errors.front().message.empty()) std::abort();
    return 0;
  }
  const cathbox::vessel::HclmReadResult again = cathbox::vessel::read_hclm(cathbox::vessel::write_hclm(read.model));
  if (!again.ok() || !(again.model == read.model)) std::abort();  // writing must be lossless
  if (read.model.segments.size() <= 6 && read.model.point_count() <= 48) {
    cathbox::vessel::MeshOptions options;
    options.ring_points = 4;
    options.subdivision_level = 1;
    const cathbox::vessel::VesselSurface surface = cathbox::vessel::build_vessel_surface(read.model, options);
    if (!surface.ok() && surface.error.empty()) std::abort();
  }
  return 0;
}
