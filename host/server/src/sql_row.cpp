#include <charconv>
#include <cmath>

#include "server/sql.hpp"

namespace cathbox::server {

namespace {
template <class... F>
struct Overload : F... {
  using F::operator()...;
};
template <class... F>
Overload(F...) -> Overload<F...>;

std::int64_t parse_integer(const std::string& s) {
  std::int64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) {
    throw StoreError(StoreError::Kind::kInternal, "database answered '" + s.substr(0, 40) + "' where an integer was expected");
  }
  return v;
}

double parse_real(const std::string& s) {
  double v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size()) {
    throw StoreError(StoreError::Kind::kInternal, "database answered '" + s.substr(0, 40) + "' where a number was expected");
  }
  return v;
}
}  // namespace

bool SqlRow::is_null(std::size_t i) const { return std::holds_alternative<std::nullptr_t>(fields_.at(i)); }

std::int64_t SqlRow::integer(std::size_t i) const {
  return std::visit(Overload{[](std::nullptr_t) -> std::int64_t { return 0; },
                             [](std::int64_t v) { return v; },
                             [](double v) { return static_cast<std::int64_t>(std::llround(v)); },
                             [](const std::string& s) { return parse_integer(s); },
                             [](const Blob& b) { return parse_integer(b.bytes); }},
                    fields_.at(i));
}

double SqlRow::real(std::size_t i) const {
  return std::visit(Overload{[](std::nullptr_t) { return 0.0; },
                             [](std::int64_t v) { return static_cast<double>(v); },
                             [](double v) { return v; },
                             [](const std::string& s) { return parse_real(s); },
                             [](const Blob& b) { return parse_real(b.bytes); }},
                    fields_.at(i));
}

std::string SqlRow::text(std::size_t i) const {
  return std::visit(Overload{[](std::nullptr_t) { return std::string(); },
                             [](std::int64_t v) { return std::to_string(v); },
                             [](double v) { return sql_double_text(v); },
                             [](const std::string& s) { return s; },
                             [](const Blob& b) { return b.bytes; }},
                    fields_.at(i));
}

std::optional<std::int64_t> SqlRow::optional_integer(std::size_t i) const {
  if (is_null(i)) return std::nullopt;
  return integer(i);
}

std::optional<SqlRow> SqlSession::query_one(std::string_view sql, const std::vector<SqlValue>& params) {
  std::vector<SqlRow> rows = query(sql, params);
  if (rows.empty()) return std::nullopt;
  return std::move(rows.front());
}

std::string sql_double_text(double v) {
  char buf[64];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  (void)ec;
  return std::string(buf, end);
}

}  // namespace cathbox::server
