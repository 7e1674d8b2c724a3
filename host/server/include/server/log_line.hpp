#pragma once
// The server's log lines (what `cathbox-server` prints while it serves): text for a terminal,
// or with `--log-format json` one JSON object a line for a log collector:
//   {"time":"2026-11-28T10:00:00.000000Z","level":"info","program":"cathbox-server","msg":"listening","url":"https://..."}
// Extra fields follow "msg" in the order given; every value is a JSON string.
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace cathbox::server {

enum class LogFormat { kText, kJson };

using LogFields = std::vector<std::pair<std::string, std::string>>;

// "text" or "json"; nullopt otherwise.
[[nodiscard]] std::optional<LogFormat> parse_log_format(std::string_view name);

// One line without its newline. Text: "cathbox-server: MESSAGE" (a "warning" adds "WARNING: ");
// the fields are only in the JSON form, the text message says what matters.
[[nodiscard]] std::string log_line(LogFormat format, std::string_view level, std::string_view message, std::int64_t time_us,
                                   const LogFields& fields = {});

}  // namespace cathbox::server
