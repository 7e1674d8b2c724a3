#pragma once
// How programs find the box: the emulator socket when a path is given (cathbox --emu PATH,
// the trainer's --emu), otherwise the first real box over hidapi; on a rig with several boxes,
// the real box with a given serial.
#include <optional>
#include <span>
#include <string>

#include "device/box_client.hpp"
#include "device/clock.hpp"
#include "device/hidapi_transport.hpp"

namespace cathbox::device {

// An Opener for BoxClient. With emu_path, the emulator must present the application
// (1209:CB01); a box sitting in its bootloader is reported as such.
[[nodiscard]] BoxClient::Opener box_opener(std::optional<std::string> emu_path, Clock& clock);
// An Opener for the real box whose serial is `serial` (hidapi enumeration).
[[nodiscard]] BoxClient::Opener box_opener_by_serial(std::string serial);

// The hidraw path of the box with `serial` among `boxes`; else an error naming the serials found.
[[nodiscard]] Result<std::string> path_of_serial(std::span<const HidDeviceInfo> boxes, const std::string& serial);

}  // namespace cathbox::device
