#pragma once
// Result values of host/server (base::Result): a status (the HTTP status the API answers with)
// plus one clear line naming what and where. Services return these; only the request boundary
// turns database exceptions into them.
#include <string>
#include <utility>

#include "base/result.hpp"

namespace cathbox::server {

struct Error {
  int status = 400;     // 400 bad input, 401, 403, 404, 409, 413, 422, 429, 503
  std::string message;  // one line: "field 'name': expected a string", "neuro.hclm:12: ..."
  int retry_after_s = 0;  // 429/503: when to try again (0: the answer's default)
};

using base::Ok;

template <class T>
using Result = base::Result<T, Error>;

using Status = Result<Ok>;

[[nodiscard]] inline Error make_error(int status, std::string message) { return Error{status, std::move(message)}; }

}  // namespace cathbox::server
