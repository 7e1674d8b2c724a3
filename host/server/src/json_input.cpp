#include "server/json_input.hpp"

#include <cmath>

namespace cathbox::server {

namespace {

// Depth of brackets outside strings; the byte where it first passes the limit, or npos.
std::size_t too_deep_at(std::string_view text) {
  int depth = 0;
  bool in_string = false;
  bool escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) {
        escaped = false;
      } else if (c == '\\') {
        escaped = true;
      } else if (c == '"') {
        in_string = false;
      }
      continue;
    }
    if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > kMaxJsonDepth) return i;
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  return std::string_view::npos;
}

// nlohmann's message without its "[json.exception.parse_error.101] parse error at line 1,
// column 5: " prefix.
std::string short_reason(const std::string& what) {
  std::string reason = what;
  if (reason.rfind("[json.exception", 0) == 0) {
    const std::size_t close = reason.find("] ");
    if (close != std::string::npos) reason = reason.substr(close + 2);
  }
  if (reason.rfind("parse error", 0) == 0) {
    const std::size_t colon = reason.find(": ");
    if (colon != std::string::npos) reason = reason.substr(colon + 2);
  }
  if (reason.size() > 200) reason = reason.substr(0, 200) + "...";
  for (char& ch : reason) {
    const auto u = static_cast<unsigned char>(ch);
    if (u < 0x20 || u >= 0x7f) ch = '?';  // "last read" quotes the input: keep the line plain
  }
  return reason;
}

bool has_nul(const nlohmann::json& v) {
  switch (v.type()) {
    case nlohmann::json::value_t::string: return v.get_ref<const std::string&>().find('\0') != std::string::npos;
    case nlohmann::json::value_t::array:
      for (const auto& x : v) {
        if (has_nul(x)) return true;
      }
      return false;
    case nlohmann::json::value_t::object:
      for (const auto& [k, x] : v.items()) {
        if (k.find('\0') != std::string::npos || has_nul(x)) return true;
      }
      return false;
    default: return false;
  }
}

}  // namespace

Result<nlohmann::json> parse_json(std::string_view text, std::string_view what) {
  const std::size_t deep = too_deep_at(text);
  if (deep != std::string_view::npos) {
    return make_error(400, std::string(what) + ": nested deeper than " + std::to_string(kMaxJsonDepth) + " levels at byte " +
                               std::to_string(deep));
  }
  try {
    nlohmann::json value = nlohmann::json::parse(text);
    if (has_nul(value)) return make_error(400, std::string(what) + ": a string holds a NUL character (\\u0000)");
    return value;
  } catch (const nlohmann::json::parse_error& e) {
    return make_error(400, std::string(what) + ": invalid JSON at byte " + std::to_string(e.byte > 0 ? e.byte - 1 : 0) + ": " +
                               short_reason(e.what()));
  } catch (const nlohmann::json::exception& e) {
    // out_of_range 406: a number too large for a double ("1e99999").
    return make_error(400, std::string(what) + ": invalid JSON: " + short_reason(e.what()));
  }
}

Result<nlohmann::json> parse_json_object(std::string_view text, std::string_view what) {
  Result<nlohmann::json> parsed = parse_json(text, what);
  if (parsed && !parsed.value().is_object()) {
    return make_error(400, std::string(what) + ": expected a JSON object, got " + parsed.value().type_name());
  }
  return parsed;
}

FieldReader::FieldReader(const nlohmann::json& object, std::string prefix) : object_(object), prefix_(std::move(prefix)) {
  if (!object_.is_object()) fail("", std::string("expected an object, got ") + object_.type_name());
}

void FieldReader::fail(const std::string& field, const std::string& message) {
  if (error_) return;
  error_ = field.empty() && prefix_.empty() ? make_error(400, message)
                                            : make_error(400, "field '" + prefix_ + field + "': " + message);
}

const nlohmann::json* FieldReader::find(const char* name, bool required) {
  if (error_) return nullptr;
  const auto it = object_.find(name);
  if (it == object_.end() || it->is_null()) {
    if (required) fail(name, "missing");
    return nullptr;
  }
  return &*it;
}

std::optional<std::string> FieldReader::optional_string(const char* name, std::size_t max_bytes) {
  const nlohmann::json* v = find(name, false);
  if (v == nullptr) return std::nullopt;
  if (!v->is_string()) {
    fail(name, std::string("expected a string, got ") + v->type_name());
    return std::nullopt;
  }
  const auto& s = v->get_ref<const std::string&>();
  if (s.size() > max_bytes) {
    fail(name, std::to_string(s.size()) + " bytes is over the limit of " + std::to_string(max_bytes));
    return std::nullopt;
  }
  return s;
}

std::string FieldReader::string(const char* name, std::size_t max_bytes) {
  if (find(name, true) == nullptr) return {};
  return optional_string(name, max_bytes).value_or(std::string());
}

std::optional<std::int64_t> FieldReader::optional_integer(const char* name, std::int64_t min, std::int64_t max) {
  const nlohmann::json* v = find(name, false);
  if (v == nullptr) return std::nullopt;
  std::int64_t n = 0;
  if (v->is_number_integer()) {
    if (v->is_number_unsigned() && v->get<std::uint64_t>() > static_cast<std::uint64_t>(INT64_MAX)) {
      fail(name, "out of range");
      return std::nullopt;
    }
    n = v->get<std::int64_t>();
  } else if (v->is_number_float() && std::isfinite(v->get<double>()) && std::floor(v->get<double>()) == v->get<double>() &&
             std::fabs(v->get<double>()) < 9.0e15) {
    n = static_cast<std::int64_t>(v->get<double>());
  } else {
    fail(name, std::string("expected an integer, got ") + (v->is_number() ? "a fraction" : v->type_name()));
    return std::nullopt;
  }
  if (n < min || n > max) {
    fail(name, std::to_string(n) + " is outside " + std::to_string(min) + ".." + std::to_string(max));
    return std::nullopt;
  }
  return n;
}

std::int64_t FieldReader::integer(const char* name, std::int64_t min, std::int64_t max) {
  if (find(name, true) == nullptr) return 0;
  return optional_integer(name, min, max).value_or(0);
}

std::optional<double> FieldReader::optional_number(const char* name) {
  const nlohmann::json* v = find(name, false);
  if (v == nullptr) return std::nullopt;
  if (!v->is_number() || !std::isfinite(v->get<double>())) {
    fail(name, std::string("expected a number, got ") + v->type_name());
    return std::nullopt;
  }
  return v->get<double>();
}

double FieldReader::number(const char* name) {
  if (find(name, true) == nullptr) return 0.0;
  return optional_number(name).value_or(0.0);
}

std::optional<bool> FieldReader::optional_boolean(const char* name) {
  const nlohmann::json* v = find(name, false);
  if (v == nullptr) return std::nullopt;
  if (!v->is_boolean()) {
    fail(name, std::string("expected true or false, got ") + v->type_name());
    return std::nullopt;
  }
  return v->get<bool>();
}

const nlohmann::json& FieldReader::array(const char* name) {
  static const nlohmann::json kNull;
  const nlohmann::json* v = find(name, true);
  if (v == nullptr) return kNull;
  if (!v->is_array()) {
    fail(name, std::string("expected an array, got ") + v->type_name());
    return kNull;
  }
  return *v;
}

void FieldReader::only(std::initializer_list<const char*> known) {
  if (error_) return;
  for (const auto& [key, value] : object_.items()) {
    bool found = false;
    for (const char* k : known) found = found || key == k;
    if (!found) {
      std::string shown = key.substr(0, 40);
      for (char& ch : shown) {
        if (static_cast<unsigned char>(ch) < 0x20) ch = '?';
      }
      fail(shown, "unknown field");
      return;
    }
  }
}

namespace {
std::string check_name(std::string_view text, bool upper_ok, const char* what) {
  if (text.empty()) return std::string(what) + " is empty";
  if (text.size() > 64) return std::string(what) + " is longer than 64 characters";
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || (upper_ok && c >= 'A' && c <= 'Z');
    if (alnum) continue;
    if (i > 0 && (c == '.' || c == '_' || c == '-')) continue;
    return std::string(what) + ": character " + std::to_string(i + 1) + " is not allowed (use " +
           (upper_ok ? "A-Z a-z" : "a-z") + " 0-9 . _ -, starting with a letter or digit)";
  }
  return {};
}
}  // namespace

bool valid_utf8(std::string_view s) {
  std::size_t i = 0;
  while (i < s.size()) {
    const auto c = static_cast<unsigned char>(s[i]);
    std::size_t n = 0;
    std::uint32_t cp = 0;
    if (c < 0x80) {
      ++i;
      continue;
    }
    if ((c & 0xe0) == 0xc0) {
      n = 1;
      cp = c & 0x1f;
    } else if ((c & 0xf0) == 0xe0) {
      n = 2;
      cp = c & 0x0f;
    } else if ((c & 0xf8) == 0xf0) {
      n = 3;
      cp = c & 0x07;
    } else {
      return false;
    }
    if (i + n >= s.size()) return false;
    for (std::size_t k = 1; k <= n; ++k) {
      const auto d = static_cast<unsigned char>(s[i + k]);
      if ((d & 0xc0) != 0x80) return false;
      cp = (cp << 6) | (d & 0x3f);
    }
    // Overlong forms, surrogates and values past U+10FFFF are not UTF-8.
    if ((n == 1 && cp < 0x80) || (n == 2 && cp < 0x800) || (n == 3 && cp < 0x10000) || cp > 0x10ffff || (cp >= 0xd800 && cp <= 0xdfff)) {
      return false;
    }
    i += n + 1;
  }
  return true;
}

std::string safe_dump(const nlohmann::json& value) {
  return value.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

std::string check_slug(std::string_view text) { return check_name(text, true, "name"); }
std::string to_slug(std::string_view text, std::string_view fallback) {
  std::string out;
  for (const char c : text) {
    const bool alnum = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9');
    if (out.empty() && !alnum) continue;
    out += alnum || c == '.' || c == '_' || c == '-' ? c : '-';
    if (out.size() == 64) break;
  }
  return out.empty() ? std::string(fallback) : out;
}

std::string check_user_name(std::string_view text) { return check_name(text, false, "user name"); }

}  // namespace cathbox::server
