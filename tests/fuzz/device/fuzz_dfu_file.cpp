// libFuzzer target for the host's firmware-file parsers: DfuFile::parse (.dfu images) and
// DfuseLayout::parse (the bootloader's memory-layout string). Property: never crash; an image
// that parses re-serialises to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "device/dfu_file.hpp"
#include "device/dfuse_layout.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using cathbox::device::DfuFile;
  const std::vector<uint8_t> bytes(data, data + size);
  auto image = DfuFile::parse(bytes, "fuzz.dfu");
  if (image.ok() && image.value().target_name.find('\0') == std::string::npos) {
    const auto again = DfuFile::write(image.value());
    auto reparsed = DfuFile::parse(again, "again.dfu");
    if (!reparsed.ok() || reparsed.value().total_bytes() != image.value().total_bytes()) std::abort();
  }
  auto layout = cathbox::device::DfuseLayout::parse(std::string(reinterpret_cast<const char*>(data), size));
  if (layout.ok() && layout.value().sectors().empty()) std::abort();
  return 0;
}
