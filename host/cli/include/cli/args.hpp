#pragma once
// The command line of one command group, parsed by CLI11: positionals, `--flag`,
// `--option VALUE` and `--option=VALUE`; `--` ends the options. Unknown options, a value given
// to a flag and an option without its value are errors (one line, in error()).
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::cli {

class Args {
 public:
  // value_options: options that take a value; flags: options that take none;
  // optional_value_options: options whose value may be left out (`--emu` alone: value "").
  Args(std::span<const std::string> argv, std::vector<std::string> value_options,
       std::vector<std::string> flags, std::vector<std::string> optional_value_options = {});

  [[nodiscard]] bool ok() const { return error_.empty(); }
  [[nodiscard]] const std::string& error() const { return error_; }
  [[nodiscard]] bool flag(std::string_view name) const;
  [[nodiscard]] std::optional<std::string> value(std::string_view name) const;
  [[nodiscard]] std::vector<std::string> values(std::string_view name) const;  // repeated options
  [[nodiscard]] const std::vector<std::string>& positionals() const { return positionals_; }

  // Parses option `name` as a number; on a bad value sets error() and returns nullopt.
  [[nodiscard]] std::optional<double> number(std::string_view name);
  [[nodiscard]] std::optional<long long> integer(std::string_view name);

 private:
  std::vector<std::pair<std::string, std::string>> options_;
  std::vector<std::string> flags_set_;
  std::vector<std::string> positionals_;
  std::string error_;
};

}  // namespace cathbox::cli
