#include "server/log_line.hpp"

#include <nlohmann/json.hpp>

#include "server/iso_time.hpp"

namespace cathbox::server {

std::optional<LogFormat> parse_log_format(std::string_view name) {
  if (name == "text") return LogFormat::kText;
  if (name == "json") return LogFormat::kJson;
  return std::nullopt;
}

std::string log_line(LogFormat format, std::string_view level, std::string_view message, std::int64_t time_us, const LogFields& fields) {
  if (format == LogFormat::kText) {
    return "cathbox-server: " + std::string(level == "warning" ? "WARNING: " : "") + std::string(message);
  }
  // ordered_json keeps the fields in the order written: time, level, program, msg, then the rest.
  nlohmann::ordered_json line;
  line["time"] = iso_time(time_us);
  line["level"] = level;
  line["program"] = "cathbox-server";
  line["msg"] = message;
  for (const auto& [key, value] : fields) line[key] = value;
  // Invalid UTF-8 (a path, a database's error text) is replaced, never a throw or a broken line.
  return line.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

}  // namespace cathbox::server
