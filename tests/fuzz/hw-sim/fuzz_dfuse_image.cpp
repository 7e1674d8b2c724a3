// libFuzzer target for cathbox-emu's DfuSe reader (`--image FILE.dfu`). Properties: never
// crash; a refusal is one line starting with the file name and a byte offset; a file that reads
// gives at most the 512 KiB flash, and it reads again to the same bytes.
#include <cstdint>
#include <cstdlib>
#include <span>
#include <string>

#include "emu/dfuse_image.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::span<const uint8_t> file(data, size);
  const auto read = cathbox::emu::read_dfuse(file, "fuzz.dfu");
  if (!read) {
    const std::string& message = read.error().message;
    if (message.rfind("fuzz.dfu: byte ", 0) != 0 || message.find('\n') != std::string::npos) std::abort();
    return 0;
  }
  const auto& image = read.value();
  if (image.flash.empty() || image.flash.size() > 512u * 1024u || image.elements == 0) std::abort();
  const auto again = cathbox::emu::read_dfuse(file, "fuzz.dfu");
  if (!again || again.value().flash != image.flash) std::abort();
  return 0;
}
