#pragma once
// How programs find the box: the emulator socket when a path is given (cathbox --emu PATH,
// the trainer's --emu), otherwise the first real box over hidapi.
#include <optional>
#include <string>

#include "device/box_client.hpp"
#include "device/clock.hpp"

namespace cathbox::device {

// An Opener for BoxClient. With emu_path, the emulator must present the application
// (1209:CB01); a box sitting in its bootloader is reported as such.
[[nodiscard]] BoxClient::Opener box_opener(std::optional<std::string> emu_path, Clock& clock);

}  // namespace cathbox::device
