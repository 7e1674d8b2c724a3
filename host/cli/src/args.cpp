#include "cli/args.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace cathbox::cli {
namespace {
bool contains(const std::vector<std::string>& list, std::string_view name) {
  return std::find(list.begin(), list.end(), name) != list.end();
}
}  // namespace

Args::Args(std::span<const std::string> argv, std::vector<std::string> value_options,
           std::vector<std::string> flags) {
  bool only_positionals = false;
  for (size_t i = 0; i < argv.size(); ++i) {
    const std::string& word = argv[i];
    if (only_positionals || word.size() < 2 || word.rfind("--", 0) != 0) {
      if (word == "--") {
        only_positionals = true;
        continue;
      }
      positionals_.push_back(word);
      continue;
    }
    std::string name = word.substr(2);
    std::optional<std::string> inline_value;
    if (const auto eq = name.find('='); eq != std::string::npos) {
      inline_value = name.substr(eq + 1);
      name.resize(eq);
    }
    if (contains(flags, name)) {
      if (inline_value) {
        error_ = "option --" + name + " takes no value";
        return;
      }
      flags_set_.push_back(name);
    } else if (contains(value_options, name)) {
      if (!inline_value) {
        if (i + 1 >= argv.size()) {
          error_ = "option --" + name + " needs a value";
          return;
        }
        inline_value = argv[++i];
      }
      options_.emplace_back(name, *inline_value);
    } else {
      error_ = "unknown option --" + name;
      return;
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
