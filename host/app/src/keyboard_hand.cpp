#include "app/keyboard_hand.hpp"

#include <algorithm>

namespace cathbox::app {

void KeyboardHand::advance(double dt_s, double min_insertion_mm, double max_insertion_mm) {
  insertion_mm_ = std::clamp(insertion_mm_ + insert_mm_s_.load(std::memory_order_relaxed) * dt_s,
                             min_insertion_mm, max_insertion_mm);
  rotation_rad_ += rotate_rad_s_.load(std::memory_order_relaxed) * dt_s;
}

int KeyboardHand::take_tool_switches() {
  const int total = switch_requests_.load(std::memory_order_relaxed);
  const int n = total - switches_taken_;
  switches_taken_ = total;
  return n;
}

}  // namespace cathbox::app
