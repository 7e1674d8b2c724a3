#pragma once
// A command group's command line, described once: its subcommands, their positionals and their
// options with help. The group parses with it (Args), prints `cathbox GROUP help` / `--help` from
// it (CLI11's formatter) and the synopsis after a usage error; nothing is written twice.
#include <functional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::cli {

struct OptionSpec {
  std::string name{};        // without the dashes: "ring"
  std::string value{};       // what it takes: "M"; empty: a flag; "[PATH]": the value may be left out
  std::string help{};        // one line
  bool required = false;   // the synopsis shows it without brackets (the command checks it)
  char short_name = 0;     // 'o': `-o X` is `--output X`
  [[nodiscard]] bool flag() const { return value.empty(); }
  [[nodiscard]] bool optional_value() const { return value.starts_with('['); }
};

struct SubcommandSpec {
  std::string name{};         // "mesh"
  std::string positionals{};  // "FILE" (as shown; the command checks them)
  std::string help{};         // one line
  std::vector<OptionSpec> options{};
};

struct GroupSpec {
  std::string name{};     // "vessel"
  std::string summary{};  // one line, also `cathbox help`'s
  std::vector<SubcommandSpec> subcommands{};
  std::string notes{};    // printed after the options in help (may be empty)
};

// "usage: cathbox GROUP SUB POSITIONALS --required V [--option V] [--flag]", one line per
// subcommand (wrapped), as printed after a usage error.
[[nodiscard]] std::string synopsis(const GroupSpec& group);
// The synopsis, then CLI11's list of the subcommands and their options, then the notes.
[[nodiscard]] std::string help(const GroupSpec& group);
[[nodiscard]] const SubcommandSpec* find_subcommand(const GroupSpec& group, std::string_view name);

// Prints "cathbox WHO: message" (WHO: the group's name unless given) and the synopsis to stderr;
// returns kExitBadInput.
int usage_error(const GroupSpec& group, const std::string& message, std::string_view who = {});

class Args;
// A group's command line `SUB ARGS...`: `help` / `--help` prints help() (exit 0); no SUB, an
// unknown one or bad options is usage_error(); else run(SUB, its parsed options).
[[nodiscard]] int run_group(const GroupSpec& group, std::span<const std::string> argv,
                            const std::function<int(std::string_view sub, Args& args)>& run);

}  // namespace cathbox::cli
