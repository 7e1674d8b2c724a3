#pragma once
// The keyboard and mouse fallback for the box: the render thread sets insertion and rotation
// speeds (atomics, never blocking), the haptic thread integrates them once per tick.
#include <atomic>

namespace cathbox::app {

class KeyboardHand {
 public:
  // Render thread.
  void set_speeds(double insert_mm_s, double rotate_rad_s) {
    insert_mm_s_.store(insert_mm_s, std::memory_order_relaxed);
    rotate_rad_s_.store(rotate_rad_s, std::memory_order_relaxed);
  }
  void request_tool_switch() { switch_requests_.fetch_add(1, std::memory_order_relaxed); }

  // Haptic thread: integrates the speeds over dt, keeping insertion within [min, max].
  void advance(double dt_s, double min_insertion_mm, double max_insertion_mm);
  // Tool switches requested since the last call.
  [[nodiscard]] int take_tool_switches();
  void reset(double insertion_mm, double rotation_rad) {
    insertion_mm_ = insertion_mm;
    rotation_rad_ = rotation_rad;
  }
  [[nodiscard]] double insertion_mm() const { return insertion_mm_; }
  [[nodiscard]] double rotation_rad() const { return rotation_rad_; }

 private:
  std::atomic<double> insert_mm_s_{0.0};
  std::atomic<double> rotate_rad_s_{0.0};
  std::atomic<int> switch_requests_{0};
  int switches_taken_ = 0;
  double insertion_mm_ = 0.0;
  double rotation_rad_ = 0.0;
};

}  // namespace cathbox::app
