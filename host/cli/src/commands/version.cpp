// `cathbox version`: the tool's version.
#include <cstdio>

#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"

namespace {
int run_version(std::span<const std::string> args) {
  if (!args.empty()) {
    std::fprintf(stderr, "cathbox version: takes no arguments\n");
    return cathbox::cli::kExitBadInput;
  }
  std::printf("cathbox %s\n", CATHBOX_VERSION);
  return cathbox::cli::kExitOk;
}
const cathbox::cli::Registrar registrar({"version", "print the tool's version", run_version});
}  // namespace
