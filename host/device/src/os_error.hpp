#pragma once
// An operating-system call that failed, as a device Error: what was being done, then errno's text.
#include <cerrno>
#include <cstring>
#include <string>

#include "device/result.hpp"

namespace cathbox::device {

[[nodiscard]] inline Error os_error(const std::string& what, Errc code = Errc::kIo) {
  return make_error(code, what + ": " + std::strerror(errno));
}

}  // namespace cathbox::device
