// firmware/hal/cbx_hal.h implemented on the current SimBoard (see sim_board.hpp).
#include <cassert>
#include <cstring>

#include "emu/sim_board.hpp"
#include "firmware/cbx_hal.h"

namespace cathbox::emu {
namespace {
thread_local SimBoard* current_board = nullptr;

SimBoard& board() {
  assert(current_board != nullptr && "the core ran outside SimBoard::Current");
  return *current_board;
}
}  // namespace

SimBoard::Current::Current(SimBoard& b) : previous_(current_board) { current_board = &b; }
SimBoard::Current::~Current() { current_board = previous_; }

}  // namespace cathbox::emu

using cathbox::emu::board;

extern "C" {

uint32_t cbx_hal_time_us(void) { return static_cast<uint32_t>(board().time_us); }

uint32_t cbx_hal_encoder_counter(cbx_axis axis) { return board().counter[axis]; }

int16_t cbx_hal_current_mA(cbx_axis axis) { return board().current_mA[axis]; }

bool cbx_hal_estop_pressed(void) { return board().estop_pressed; }

void cbx_hal_actuator_set(cbx_axis axis, int16_t drive_permille) { board().drive_permille[axis] = drive_permille; }

uint16_t cbx_hal_supply_mV(void) { return board().supply_mV; }

void cbx_hal_led_set(bool on) { board().led = on; }

void cbx_hal_watchdog_kick(void) { ++board().watchdog_kicks; }

void cbx_hal_bootloader_request(void) {
  board().drive_permille = {0, 0};
  board().bootloader_requested = true;
}

bool cbx_hal_store_load(void* data, size_t size) {
  const auto& store = board().store;
  if (store.size() != size) return false;
  std::memcpy(data, store.data(), size);
  return true;
}

bool cbx_hal_store_save(const void* data, size_t size) {
  auto& store = board().store;
  const auto* bytes = static_cast<const uint8_t*>(data);
  store.assign(bytes, bytes + size);
  ++board().store_saves;
  return true;
}

}  // extern "C"
