// libFuzzer target for cathbox-emu's hand-script parser (--hand-insertion / --hand-rotation):
// never crash; a parsed script answers every time query.
#include <cstdint>
#include <cstdlib>
#include <string>

#include "emu/hand_script.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  auto script = cathbox::emu::HandScript::parse(std::string(reinterpret_cast<const char*>(data), size));
  if (script.ok()) {
    for (uint64_t t : {0ull, 1000ull, 1'000'000ull, 1ull << 40}) (void)script.value().at(t);
  }
  return 0;
}
