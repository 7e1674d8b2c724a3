#include "cli/registry.hpp"

namespace cathbox::cli {
namespace {
std::vector<Command>& table() {
  static std::vector<Command> commands;
  return commands;
}
}  // namespace

void register_command(const Command& command) { table().push_back(command); }
const std::vector<Command>& commands() { return table(); }

}  // namespace cathbox::cli
