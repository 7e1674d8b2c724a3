#include "cli/usage.hpp"

#include <cstdio>

#include <CLI/CLI.hpp>

#include "cli/args.hpp"
#include "cli/exit_codes.hpp"

namespace cathbox::cli {
namespace {

constexpr std::size_t kWidth = 100;  // synopsis lines wrap before this column

// How an option appears in the synopsis: "--case FILE", "[--ring M]", "[--json]", "-o OUT".
std::string synopsis_word(const OptionSpec& o) {
  std::string word = o.short_name != 0 ? std::string("-") + o.short_name : "--" + o.name;
  if (!o.flag()) word += " " + o.value;
  return o.required ? word : "[" + word + "]";
}

// CLI11's names for an option: "-o,--output" or "--ring".
std::string cli11_names(const OptionSpec& o) {
  return (o.short_name != 0 ? std::string("-") + o.short_name + "," : std::string()) + "--" + o.name;
}

}  // namespace

std::string synopsis(const GroupSpec& group) {
  std::string out;
  for (const SubcommandSpec& sub : group.subcommands) {
    std::string line = (out.empty() ? "usage: " : "       ") + std::string("cathbox ") + group.name + " " + sub.name;
    if (!sub.positionals.empty()) line += " " + sub.positionals;
    const std::string indent(line.size() + 1, ' ');
    for (const OptionSpec& o : sub.options) {
      const std::string word = synopsis_word(o);
      const std::size_t last_line = line.rfind('\n') == std::string::npos ? 0 : line.rfind('\n') + 1;
      if (line.size() - last_line + 1 + word.size() > kWidth) line += "\n" + indent.substr(1);
      else line += " ";
      line += word;
    }
    out += line + "\n";
  }
  return out;
}

std::string help(const GroupSpec& group) {
  CLI::App app(group.summary, "cathbox " + group.name);
  app.set_help_flag();
  app.footer(group.notes);
  for (const SubcommandSpec& sub : group.subcommands) {
    CLI::App* s = app.add_subcommand(sub.name, sub.positionals.empty() ? sub.help : sub.positionals + ": " + sub.help);
    s->set_help_flag();
    for (const OptionSpec& o : sub.options) {
      if (o.flag()) s->add_flag(cli11_names(o), o.help);
      else s->add_option(cli11_names(o), o.help)->type_name(o.value)->required(o.required);
    }
  }
  return synopsis(group) + "\n" + app.help("", CLI::AppFormatMode::All);
}

const SubcommandSpec* find_subcommand(const GroupSpec& group, std::string_view name) {
  for (const SubcommandSpec& sub : group.subcommands) {
    if (sub.name == name) return &sub;
  }
  return nullptr;
}

int usage_error(const GroupSpec& group, const std::string& message, std::string_view who) {
  const std::string name(who.empty() ? std::string_view(group.name) : who);
  std::fprintf(stderr, "cathbox %s: %s\n%s", name.c_str(), message.c_str(), synopsis(group).c_str());
  return kExitBadInput;
}

int run_group(const GroupSpec& group, std::span<const std::string> argv,
              const std::function<int(std::string_view sub, Args& args)>& run) {
  if (argv.empty()) return usage_error(group, "missing subcommand");
  const std::string& sub = argv[0];
  if (sub == "help" || sub == "--help") {
    std::printf("%s", help(group).c_str());
    return kExitOk;
  }
  const SubcommandSpec* described = find_subcommand(group, sub);
  if (described == nullptr) return usage_error(group, "unknown subcommand '" + sub + "'");
  Args args(argv.subspan(1), described->options);
  if (!args.ok()) return usage_error(group, args.error());
  return run(sub, args);
}

}  // namespace cathbox::cli
