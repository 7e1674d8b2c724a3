#include "cli/args.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <CLI/CLI.hpp>

namespace cathbox::cli {
namespace {
bool contains(const std::vector<std::string>& list, std::string_view name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}
}  // namespace

namespace {
std::vector<OptionSpec> specs(const std::vector<std::string>& value_options, const std::vector<std::string>& flags,
                              const std::vector<std::string>& optional_value_options) {
  std::vector<OptionSpec> out;
  for (const std::string& name : value_options) out.push_back({.name = name, .value = "VALUE"});
  for (const std::string& name : optional_value_options) out.push_back({.name = name, .value = "[VALUE]"});
  for (const std::string& name : flags) out.push_back({.name = name});
  return out;
}
}  // namespace

Args::Args(std::span<const std::string> argv, std::vector<std::string> value_options,
           std::vector<std::string> flags, std::vector<std::string> optional_value_options)
    : Args(argv, specs(value_options, flags, optional_value_options)) {}

Args::Args(std::span<const std::string> argv_in, std::span<const OptionSpec> options) {
  // CLI11 recognises the options; words it does not know come back in order, as positionals,
  // unknown options (the first is the error) and the `--` that ends the options.
  CLI::App app("", "cathbox");
  app.set_help_flag("--help", "this text");
  app.allow_extras();
  app.option_defaults()->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  std::vector<std::string> flags;
  std::vector<std::string> optional_value_options;
  std::vector<std::pair<std::string, CLI::Option*>> values;
  std::vector<std::pair<std::string, CLI::Option*>> switches;
  std::vector<std::string> argv(argv_in.begin(), argv_in.end());
  for (const OptionSpec& o : options) {
    if (o.short_name != 0) std::replace(argv.begin(), argv.end(), std::string("-") + o.short_name, "--" + o.name);  // `-o` is `--output`
    if (o.flag()) {
      flags.push_back(o.name);
      switches.emplace_back(o.name, app.add_flag("--" + o.name, o.help)->disable_flag_override());
      continue;
    }
    if (o.optional_value()) optional_value_options.push_back(o.name);
    values.emplace_back(o.name, app.add_option("--" + o.name, o.help)->expected(0, 1)->type_name(o.value));
  }
  try {
    app.parse(std::vector<std::string>(argv.rbegin(), argv.rend()));
  } catch (const CLI::CallForHelp&) {
    const std::string text = app.help();  // from "Options:" on (the command's usage is the summary)
    throw HelpRequested(text.substr(std::min(text.find("Options:"), text.size())));
  } catch (const CLI::ParseError&) {
    // The one error CLI11 raises here: a value given to a flag (`--json=1`).
    const auto given = std::find_if(argv.begin(), argv.end(), [&](const std::string& word) {
      const auto eq = word.find('=');
      return word.rfind("--", 0) == 0 && eq != std::string::npos && contains(flags, word.substr(2, eq - 2));
    });
    error_ = "option " + (given == argv.end() ? std::string("--") : given->substr(0, given->find('='))) + " takes no value";
    return;
  }
  for (const auto& [name, option] : values) {
    for (const std::string& value : option->results()) {
      if (value.empty() && !contains(optional_value_options, name)) {
        error_ = "option --" + name + " needs a value";
        return;
      }
      options_.emplace_back(name, value);
    }
  }
  for (const auto& [name, option] : switches) {
    if (option->count() > 0) flags_set_.push_back(name);
  }
  bool only_positionals = false;
  for (const std::string& word : app.remaining()) {
    if (!only_positionals && word == "--") {
      only_positionals = true;
    } else if (!only_positionals && word.size() >= 2 && word.rfind("--", 0) == 0) {
      error_ = "unknown option --" + word.substr(2, word.find('=') - 2);
      return;
    } else {
      positionals_.push_back(word);
    }
  }
}

bool Args::flag(std::string_view name) const { return contains(flags_set_, name); }

std::optional<std::string> Args::value(std::string_view name) const {
  std::optional<std::string> last;
  for (const auto& [key, val] : options_) {
    if (key == name) last = val;
  }
  return last;
}

std::vector<std::string> Args::values(std::string_view name) const {
  std::vector<std::string> out;
  for (const auto& [key, val] : options_) {
    if (key == name) out.push_back(val);
  }
  return out;
}

std::optional<double> Args::number(std::string_view name) {
  const auto text = value(name);
  if (!text) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const double v = std::strtod(text->c_str(), &end);
  if (text->empty() || *end != '\0' || errno != 0 || !std::isfinite(v)) {
    error_ = "option --" + std::string(name) + ": '" + *text + "' is not a finite number";
    return std::nullopt;
  }
  return v;
}

std::optional<std::vector<double>> Args::numbers(std::string_view name, std::size_t count, char separator) {
  const auto text = value(name);
  if (!text) return std::nullopt;
  std::vector<double> out;
  bool good = true;
  for (const char* p = text->c_str(); good;) {
    char* end = nullptr;
    errno = 0;
    const double v = std::strtod(p, &end);
    good = end != p && errno == 0 && std::isfinite(v) && (*end == separator || *end == '\0');
    if (good) out.push_back(v);
    if (!good || *end == '\0') break;
    p = end + 1;
  }
  if (!good || out.size() != count) {
    const std::string separated = separator == ',' ? "comma" : std::string("'") + separator + "'";
    error_ = "option --" + std::string(name) + ": '" + *text + "' is not " + std::to_string(count) + " " + separated +
             "-separated finite numbers";
    return std::nullopt;
  }
  return out;
}

std::optional<long long> Args::integer(std::string_view name) {
  const auto text = value(name);
  if (!text) return std::nullopt;
  char* end = nullptr;
  errno = 0;
  const long long v = std::strtoll(text->c_str(), &end, 0);
  if (text->empty() || *end != '\0' || errno != 0) {
    error_ = "option --" + std::string(name) + ": '" + *text + "' is not an integer";
    return std::nullopt;
  }
  return v;
}

}  // namespace cathbox::cli
