#pragma once
// JSON from outside (request bodies, WebSocket messages): parsed with nlohmann-json after a
// depth check, read field by field. Every problem is one line naming the byte or the field:
//   body: invalid JSON at byte 17: syntax error while parsing object key
//   body: nested deeper than 32 levels at byte 40
//   field 'role': expected one of trainee, instructor, admin
// Strings holding U+0000 are refused (PostgreSQL text cannot store them, and both stores must
// keep the same data).
#include <cstdint>
#include <initializer_list>
#include <optional>
#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

#include "server/result.hpp"

namespace cathbox::server {

inline constexpr int kMaxJsonDepth = 32;

// Parses `text` as one JSON value; `what` names it in errors ("body", "message").
[[nodiscard]] Result<nlohmann::json> parse_json(std::string_view text, std::string_view what = "body");
// Same, and the value must be an object.
[[nodiscard]] Result<nlohmann::json> parse_json_object(std::string_view text, std::string_view what = "body");

// Reads fields of one object; the first problem is kept and later reads return defaults.
class FieldReader {
 public:
  // `prefix` goes before field names in errors ("criteria[2].").
  explicit FieldReader(const nlohmann::json& object, std::string prefix = "");

  std::string string(const char* name, std::size_t max_bytes);
  std::optional<std::string> optional_string(const char* name, std::size_t max_bytes);
  std::int64_t integer(const char* name, std::int64_t min, std::int64_t max);
  std::optional<std::int64_t> optional_integer(const char* name, std::int64_t min, std::int64_t max);
  double number(const char* name);
  std::optional<double> optional_number(const char* name);
  std::optional<bool> optional_boolean(const char* name);
  // The field must be present and an array / object (returned as-is, or null on error).
  const nlohmann::json& array(const char* name);
  // Fails on any field not in `known` (catches typos in requests).
  void only(std::initializer_list<const char*> known);
  void fail(const std::string& field, const std::string& message);

  [[nodiscard]] bool ok() const { return !error_; }
  [[nodiscard]] const Error& error() const { return *error_; }

 private:
  const nlohmann::json* find(const char* name, bool required);
  const nlohmann::json& object_;
  std::string prefix_;
  std::optional<Error> error_;
};

// Whether `s` is well-formed UTF-8 (no overlong forms, surrogates or values past U+10FFFF).
[[nodiscard]] bool valid_utf8(std::string_view s);

// Compact JSON text; invalid UTF-8 in strings (which only our own bugs could put there, since
// parse_json refuses it) becomes U+FFFD instead of an exception.
[[nodiscard]] std::string safe_dump(const nlohmann::json& value);

// A name for things in the library and on the wire (cases, rigs): 1-64 characters of
// [A-Za-z0-9._-], starting with a letter or digit. Empty string when fine, else why not.
[[nodiscard]] std::string check_slug(std::string_view text);
// `text` made into a slug check_slug accepts: other characters become '-', leading ones that
// may not start a slug are dropped, cut at 64; `fallback` when nothing is left.
[[nodiscard]] std::string to_slug(std::string_view text, std::string_view fallback);
// A user name: 1-64 characters of [a-z0-9._-], starting with a letter or digit.
[[nodiscard]] std::string check_user_name(std::string_view text);

}  // namespace cathbox::server
