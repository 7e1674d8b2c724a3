#pragma once
// Result values of host/server: a status (the HTTP status the API answers with) plus one clear
// line naming what and where. Services return these; only the request boundary turns database
// exceptions into them.
#include <string>
#include <utility>
#include <variant>

namespace cathbox::server {

struct Error {
  int status = 400;     // 400 bad input, 401, 403, 404, 409, 413, 422, 429, 503
  std::string message;  // one line: "field 'name': expected a string", "neuro.hclm:12: ..."
  int retry_after_s = 0;  // 429/503: when to try again (0: the answer's default)
};

struct Ok {};

template <class T>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::move(value)) {}      // NOLINT: implicit on purpose
  Result(Error error) : v_(std::move(error)) {}  // NOLINT
  [[nodiscard]] bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  [[nodiscard]] T& value() { return std::get<0>(v_); }
  [[nodiscard]] const T& value() const { return std::get<0>(v_); }
  [[nodiscard]] const Error& error() const { return std::get<1>(v_); }

 private:
  std::variant<T, Error> v_;
};

using Status = Result<Ok>;

[[nodiscard]] inline Error make_error(int status, std::string message) { return Error{status, std::move(message)}; }

}  // namespace cathbox::server
