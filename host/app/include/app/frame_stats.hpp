#pragma once
// Frame times of a run: median, 99th percentile and mean frame rate, for the HUD and --bench.
#include <cstdint>
#include <vector>

namespace cathbox::app {

class FrameStats {
 public:
  void add(std::int64_t frame_us) { frames_us_.push_back(frame_us); }
  [[nodiscard]] std::size_t count() const { return frames_us_.size(); }
  [[nodiscard]] double percentile_us(double p) const;  // p in [0, 100]
  [[nodiscard]] double mean_fps() const;

 private:
  std::vector<std::int64_t> frames_us_;
};

}  // namespace cathbox::app
