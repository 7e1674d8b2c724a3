#pragma once
// A small command-line parser shared by all command groups: positionals, `--flag`,
// `--option VALUE` and `--option=VALUE`. Unknown options are errors.
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace cathbox::cli {

class Args {
 public:
  // value_options: options that take a value; flags: options that take none.
  Args(std::span<const std::string> argv, std::vector<std::string> value_options,
       std::vector<std::string> flags);

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
