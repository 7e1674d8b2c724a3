#pragma once
// The one result type of Cathbox's C++ modules: a value, or an error saying what went wrong
// (recoverable errors are values; exceptions only at the application boundary). C++23's
// std::expected is not in GCC 12 and Debian 12 has no tl-expected, hence this small header.
//
// The error payload is the module's: base::Error (one line) unless the module needs more
// (host/device adds an Errc code, host/server the HTTP status). Modules name their own
// alias, e.g. `template <class T> using Result = base::Result<T, Error>;`.
#include <string>
#include <utility>
#include <variant>

namespace cathbox::base {

// One clear line naming the file / field / device and what went wrong.
struct Error {
  std::string message;
};

// The value of a Result that has none (see Status).
struct Ok {};

template <class T, class E = Error>
class [[nodiscard]] Result {
 public:
  Result(T value) : v_(std::in_place_index<0>, std::move(value)) {}  // NOLINT: implicit on purpose
  Result(E error) : v_(std::in_place_index<1>, std::move(error)) {}  // NOLINT
  [[nodiscard]] bool ok() const { return v_.index() == 0; }
  explicit operator bool() const { return ok(); }
  [[nodiscard]] T& value() { return std::get<0>(v_); }
  [[nodiscard]] const T& value() const { return std::get<0>(v_); }
  [[nodiscard]] const E& error() const { return std::get<1>(v_); }
  [[nodiscard]] T* operator->() { return &value(); }
  [[nodiscard]] const T* operator->() const { return &value(); }
  [[nodiscard]] T& operator*() { return value(); }
  [[nodiscard]] const T& operator*() const { return value(); }

 private:
  std::variant<T, E> v_;
};

// Success or an error, nothing else.
template <class E = Error>
using Status = Result<Ok, E>;

}  // namespace cathbox::base
