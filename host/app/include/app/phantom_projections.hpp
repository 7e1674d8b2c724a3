#pragma once
// The head phantom's projections for the fluoroscopic renderer (path length per pixel, row 0 at
// the top; flow::HeadPhantom::project): the current one, a spare (the pose's other readout, or
// the projection before), and the worker threads that project a new pose in the background.
// CPU only: the renderer uploads what use() makes current.
#include <cstdint>
#include <future>
#include <optional>
#include <vector>

#include "flow/c_arm.hpp"
#include "flow/head_phantom.hpp"

namespace cathbox::app {

class PhantomProjections {
 public:
  struct Size {
    int width = 0;
    int height = 0;
  };
  // A projection wanted (`key`: pose, size and scene generation, hashed by the renderer) and
  // the other readout's at the same pose (binned fluoroscopy <-> a full-size run).
  struct Request {
    std::uint64_t key = 0;
    Size size;
    std::uint64_t other_key = 0;
    Size other;
  };
  enum class Outcome {
    kSame,     // the current projection is the one asked for
    kChanged,  // another became current: from the spare, a worker, or projected at once
    kWaiting,  // projecting on a worker meanwhile; the current one stays
  };

  // Makes the request's projection current. With background projection on and `can_hold` (a
  // last image to show meanwhile), a pose not ready is projected on a worker (one at a time; a
  // pose passed by while it ran is dropped); otherwise at once. A pose's first projection is
  // followed, in the background, by the other readout's, which becomes the spare.
  // `projected`: a projection was newly made (not swapped in from the spare).
  Outcome use(const flow::HeadPhantom& phantom, const flow::CArm& carm, const Request& request, bool can_hold,
              bool& projected);
  [[nodiscard]] const std::vector<float>& path() const { return path_; }
  [[nodiscard]] std::uint64_t key() const { return key_; }
  // Nothing is current (a new phantom: the next use() projects).
  void forget() { key_ = 0; }

  void set_background(bool on) { background_ = on; }
  // Blocks until the background projections under way (if any) are done.
  void finish() {
    if (pending_) pending_->path.wait();
    if (other_pending_) other_pending_->path.wait();
  }

 private:
  struct Projection {
    std::uint64_t key = 0;
    std::future<std::vector<float>> path;
  };
  void adopt(std::vector<float> path, const flow::HeadPhantom& phantom, const flow::CArm& carm, const Request& request);
  static Projection launch(const flow::HeadPhantom& phantom, const flow::CArm& carm, std::uint64_t key, Size size);

  std::uint64_t key_ = 0;
  std::vector<float> path_;
  std::uint64_t spare_key_ = 0;
  std::vector<float> spare_path_;
  bool background_ = false;
  std::optional<Projection> pending_;        // the background projection under way
  std::optional<Projection> other_pending_;  // the other readout's, for the spare
};

}  // namespace cathbox::app
