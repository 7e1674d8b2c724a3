#pragma once
// Result values of hw-sim (base::Result): a value or one clear line.
#include "base/result.hpp"

namespace cathbox::emu {

using base::Error;
template <class T>
using Result = base::Result<T>;
// Success or one clear line.
using Status = base::Status<>;

}  // namespace cathbox::emu
