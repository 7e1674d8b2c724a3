#pragma once
// A new wall for a changed lumen, built beside the old one and swapped into the simulator
// between two ticks, at a tick the simulation decides.
//
// request(model, tick) hands the lumen to the builder (re-mesh + collision tree + MeshWall:
// WallBuilder) and schedules the swap for tick + latency_ticks. poll() swaps it in at exactly
// that tick in both modes, so which wall a tick runs on, and so every result, is a function of
// the run's inputs alone, whatever the machine's load or the threads' timing (a record replays
// a live run bit for bit):
//  - kSynchronous (headless, tests, replay, the browser): the wall is built inside request().
//  - kWorker (the live haptic loop): a worker thread builds it while the ticks run on the old
//    wall. A build not done by the due tick makes that tick wait for it (waits() counts such
//    swaps, wait_tally() how long, in fixed storage): the haptic tick costs its step alone as long
//    as the build takes less than the latency (bench_angioplasty measures it against the
//    300 ms), and a late build stalls the loop for its remaining time, never changes the tick.
// The old wall stays valid (owned here) until the swap, and is destroyed afterwards off the
// haptic thread (by the worker; in synchronous mode at once). One wall is built at a time: a
// request while one is pending is refused (the caller asks again after the swap).
//
// Renderers follow the walls through generation() (the swaps so far, 0 for the initial wall)
// and surface() (the present wall's WallSurface: the widened model and its mesh), both readable
// from any thread; the swap publishes the new surface before the generation.
#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>
#include <vector>

#include "base/atomic_shared_ptr.hpp"
#include "base/result.hpp"
#include "collision/obb_tree.hpp"
#include "tool/simulator.hpp"
#include "tool/wall_model.hpp"
#include "vessel/vessel_model.hpp"

namespace cathbox::tool {

// Builds the wall of a lumen (thread-safe: called on the worker).
using WallBuilder = std::function<base::Result<std::unique_ptr<WallModel>>(const vessel::VesselModel&)>;
// The vessel's wall as build_world() makes it: surface (vessel_mesher), OBB tree, MeshWall.
// With a cache, the tree reuses the regions (segments, junctions, caps) whose surface is the
// same as in the last wall built with it (collision::TreeCache): the same tree, built faster.
[[nodiscard]] base::Result<std::unique_ptr<WallModel>> build_mesh_wall(const vessel::VesselModel& model,
                                                                       collision::TreeCache* cache = nullptr);
// The same wall on a surface meshed elsewhere (`made`: the case's own, as a build that cannot
// mesh reads it; the WebAssembly session has no OpenSubdiv): it holds `model` as build_mesh_wall
// does, so that its lumen read and lumen axis are the same as a wall meshed here.
[[nodiscard]] base::Result<std::unique_ptr<WallModel>> build_mesh_wall(const vessel::VesselModel& model,
                                                                       vessel::SurfaceMesh made);
// build_mesh_wall with one TreeCache carried from each wall to the next (copies share it; one
// build at a time, as WallSwap builds). Build the first wall with it too, so that the first
// rebuild already reuses the regions a balloon did not touch.
[[nodiscard]] WallBuilder cached_mesh_wall_builder();

class WallSwap {
 public:
  enum class Mode { kSynchronous, kWorker };
  static constexpr std::int64_t kDefaultLatencyTicks = 300;  // 300 ms at 1 kHz

  WallSwap(std::unique_ptr<WallModel> initial, WallBuilder builder, Mode mode,
           std::int64_t latency_ticks = kDefaultLatencyTicks);
  ~WallSwap();
  WallSwap(const WallSwap&) = delete;
  WallSwap& operator=(const WallSwap&) = delete;

  // Switches between the modes (a session knows it only when it starts its clock); takes
  // effect when no wall is pending. The worker thread starts with the first worker build.
  void set_mode(Mode mode);
  [[nodiscard]] Mode mode() const { return mode_; }

  // The wall the simulator uses now (give it to the Simulator's constructor).
  [[nodiscard]] const WallModel& wall() const { return *current_; }
  // Asks for a wall of `model` (copied), due at tick `now` + latency; false while one is pending.
  bool request(const vessel::VesselModel& model, std::int64_t now);
  // Between two ticks, on the haptic thread: swaps the requested wall into `sim` at its due
  // tick (waiting for the builder if it is not done). True when it swapped.
  bool poll(Simulator& sim, std::int64_t now);
  // Called on the polling thread when a due wall's builder is not done, before the tick waits
  // for it (tests release a builder they hold there, to run the late path in virtual time).
  void set_wait_hook(std::function<void()> hook) { wait_hook_ = std::move(hook); }
  // Blocks until the builder is idle (tests, benches, the end of a run; never the haptic loop).
  void drain();

  [[nodiscard]] bool pending() const { return due_tick_.has_value(); }
  [[nodiscard]] std::int64_t due_tick() const { return due_tick_.value_or(-1); }
  [[nodiscard]] std::uint64_t requests() const { return requests_; }
  [[nodiscard]] std::uint64_t swaps() const { return swaps_; }
  // Any thread: the walls swapped in so far, and the present wall's surface (empty for a wall
  // without one).
  [[nodiscard]] std::uint64_t generation() const { return generation_.load(std::memory_order_acquire); }
  [[nodiscard]] std::shared_ptr<const WallSurface> surface() const;
  // Swaps whose due tick had to wait for the builder (kWorker only), and how long each waited
  // in wall seconds (a figure of the machine, never fed back into the simulation).
  struct WaitTally {
    static constexpr std::size_t kRecent = 128;  // the last waits kept for a median
    std::uint64_t count = 0;
    double total_seconds = 0.0, max_seconds = 0.0;
    std::array<double, kRecent> recent{};  // ring: the wait of swap k at recent[k % kRecent]
    void add(double seconds);
    // The recorded waits, oldest first (at most kRecent of them).
    [[nodiscard]] std::vector<double> recent_seconds() const;
  };
  [[nodiscard]] std::uint64_t waits() const { return wait_tally_.count; }
  [[nodiscard]] const WaitTally& wait_tally() const { return wait_tally_; }
  [[nodiscard]] std::uint64_t failures() const { return failures_; }
  [[nodiscard]] const std::string& last_error() const { return last_error_; }
  // Seconds the builder took for each wall so far (measured on the builder's thread), in wall
  // time and in that thread's CPU time.
  [[nodiscard]] std::vector<double> build_seconds() const;
  [[nodiscard]] std::vector<double> build_cpu_seconds() const;

 private:
  void work();
  void retire(std::unique_ptr<WallModel> old);

  std::unique_ptr<WallModel> current_;
  WallBuilder builder_;
  Mode mode_;
  std::int64_t latency_;
  std::optional<std::int64_t> due_tick_;
  std::uint64_t requests_ = 0, swaps_ = 0, failures_ = 0;
  WaitTally wait_tally_;
  std::function<void()> wait_hook_;
  std::string last_error_;
  std::atomic<std::uint64_t> generation_{0};
  base::AtomicSharedPtr<const WallSurface> surface_;

  // Shared with the builder thread (under mutex_).
  mutable std::mutex mutex_;
  std::condition_variable wake_, idle_;
  // The lumen to build: request() copies into job_model_ (reusing its storage: no allocation
  // once the first request has shaped it), the worker swaps it with work_model_.
  vessel::VesselModel job_model_, work_model_;
  bool has_job_ = false;
  std::optional<base::Result<std::unique_ptr<WallModel>>> done_;
  std::vector<std::unique_ptr<WallModel>> retired_;
  std::vector<double> build_seconds_, build_cpu_seconds_;
  bool busy_ = false;
  bool stop_ = false;
  std::thread worker_;
};

}  // namespace cathbox::tool
