// Fuzz target for cathbox-trainer's command line: the input is split at NUL bytes into
// arguments. Parsing must never crash, and must either give options or one line of error.
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <vector>

#include "app/trainer_options.hpp"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::vector<std::string> words(1);
  for (size_t i = 0; i < size && words.size() < 64; ++i) {
    if (data[i] == 0) {
      words.emplace_back();
    } else {
      words.back().push_back(static_cast<char>(data[i]));
    }
  }
  std::vector<const char*> args;
  for (const std::string& w : words) args.push_back(w.c_str());
  const cathbox::app::OptionsResult r = cathbox::app::parse_trainer_options(args);
  if (!r.options && (r.error.empty() || r.error.find('\n') != std::string::npos)) std::abort();
  if (r.options && (r.options->width < 64 || r.options->height < 64 || r.options->frames < 0)) std::abort();
  return 0;
}
