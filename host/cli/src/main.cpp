// `cathbox`: the hardware engineer's and developer's command-line tool.
#include <cstdio>
#include <exception>
#include <string>
#include <vector>

#include "cli/exit_codes.hpp"
#include "cli/registry.hpp"

namespace {
void print_help() {
  std::printf("usage: cathbox COMMAND [ARGS...]\n\ncommands:\n");
  for (const auto& command : cathbox::cli::commands()) {
    std::printf("  %-10.*s %.*s\n", static_cast<int>(command.name.size()), command.name.data(),
                static_cast<int>(command.summary.size()), command.summary.data());
  }
  std::printf("\nexit codes: 0 ok, 1 failure, 2 bad input, 3 no device, 4 incompatible protocol, "
              "5 device error\n");
}
}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "--help" ||
      std::string(argv[1]) == "-h") {
    print_help();
    return argc < 2 ? cathbox::cli::kExitBadInput : cathbox::cli::kExitOk;
  }
  const std::string name = argv[1];
  const std::vector<std::string> args(argv + 2, argv + argc);
  for (const auto& command : cathbox::cli::commands()) {
    if (command.name == name) {
      try {
        return command.run(args);
      } catch (const std::exception& e) {
        std::fprintf(stderr, "cathbox %s: %s\n", name.c_str(), e.what());
        return cathbox::cli::kExitFailure;
      }
    }
  }
  std::fprintf(stderr, "cathbox: unknown command '%s' (see 'cathbox help')\n", name.c_str());
  return cathbox::cli::kExitBadInput;
}
