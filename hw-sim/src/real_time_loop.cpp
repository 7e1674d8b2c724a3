#include "emu/real_time_loop.hpp"

namespace cathbox::emu {

void RealTimeLoop::run(Emulator& emu, const std::atomic<bool>& stop, uint64_t duration_us,
                       const std::function<void(uint64_t)>& each) {
  run_box(emu, stop, duration_us, each);
}

}  // namespace cathbox::emu
