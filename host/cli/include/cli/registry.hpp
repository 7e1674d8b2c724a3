#pragma once
// Command registry of the `cathbox` tool: each command group registers itself once.
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::cli {

struct Command {
  std::string_view name;     // first word on the command line, e.g. "vessel"
  std::string_view summary;  // one line for `cathbox help`
  int (*run)(std::span<const std::string> args);  // args after the name; returns an exit code
};

void register_command(const Command& command);
[[nodiscard]] const std::vector<Command>& commands();

struct Registrar {
  explicit Registrar(const Command& command) { register_command(command); }
};

}  // namespace cathbox::cli
