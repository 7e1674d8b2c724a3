#pragma once
// Result values of host/device (base::Result): an error code plus one clear line. No exceptions
// below the CLI.
#include <string>
#include <utility>

#include "base/result.hpp"

namespace cathbox::device {

enum class Errc {
  kNoDevice,      // nothing to open (no box, no bootloader, no emulator socket)
  kDisconnected,  // the device went away during the operation
  kTimeout,       // no answer within the deadline
  kStall,         // the device refused a control request
  kIo,            // an operating-system call failed
  kBadReport,     // a report failed to decode (length, id, CRC, range)
  kIncompatible,  // the box speaks another protocol major version
  kBadImage,      // a firmware image failed its checks (nothing was erased)
  kVerify,        // read-back differs from what was written
  kDeviceError,   // the device reported an error state
  kBadArgument    // the caller passed something unusable
};

struct Error {
  Errc code;
  std::string message;  // one line, names the device / file / field
};

using base::Ok;

template <class T>
using Result = base::Result<T, Error>;

using Status = Result<Ok>;

[[nodiscard]] inline Error make_error(Errc code, std::string message) {
  return Error{code, std::move(message)};
}

}  // namespace cathbox::device
