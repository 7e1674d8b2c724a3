// Replay driver for fuzz targets in non-fuzz builds: runs LLVMFuzzerTestOneInput on every
// file named on the command line, or on every regular file inside a named folder.
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size);

namespace {
int replay_file(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "%s: cannot open\n", path.c_str());
    return 1;
  }
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  LLVMFuzzerTestOneInput(bytes.data(), bytes.size());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  int failures = 0;
  int replayed = 0;
  for (int i = 1; i < argc; ++i) {
    const std::filesystem::path arg(argv[i]);
    if (std::filesystem::is_directory(arg)) {
      for (const auto& entry : std::filesystem::recursive_directory_iterator(arg)) {
        if (entry.is_regular_file()) {
          failures += replay_file(entry.path());
          ++replayed;
        }
      }
    } else {
      failures += replay_file(arg);
      ++replayed;
    }
  }
  // Also exercise the empty input and a few tiny ones.
  const uint8_t tiny[4] = {0, 1, 0xff, 0x7f};
  for (size_t n = 0; n <= sizeof tiny; ++n) LLVMFuzzerTestOneInput(tiny, n);
  std::printf("replayed %d inputs, %d unreadable\n", replayed, failures);
  return failures == 0 && replayed > 0 ? 0 : 1;
}
