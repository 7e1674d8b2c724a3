#pragma once
// One job at a time on a thread of its own, beside the caller (the Simulator's released coils,
// solved while the haptic thread solves the attached tools): start(fn, ctx) runs fn(ctx) there,
// finish() returns when that run is over. The thread is made at the first start(),
// by the caller's thread, so it inherits that thread's scheduling (the haptic thread's
// SCHED_FIFO where the rig grants it). Not threaded (set_threaded(false), and the WebAssembly
// build by default): start() runs the job there and then. Either way the job reads and writes
// only what the caller leaves alone between start() and finish(), so its results are the same.
#include <atomic>
#include <condition_variable>
#include <mutex>
#include <thread>

namespace cathbox::tool {

class BackgroundJob {
 public:
  using Fn = void (*)(void*);
  BackgroundJob();
  ~BackgroundJob();
  BackgroundJob(const BackgroundJob&) = delete;
  BackgroundJob& operator=(const BackgroundJob&) = delete;

  void set_threaded(bool on);
  [[nodiscard]] bool threaded() const { return threaded_; }
  // Threaded unless in the WebAssembly build or on a single core.
  [[nodiscard]] static bool threaded_by_default();
  void start(Fn fn, void* ctx);
  // Waits for the started run (spinning, then yielding: the caller is a real-time loop whose
  // wait is short and whose thread CPU time is its tick's cost), then returns. Nothing
  // started: returns at once.
  void finish();
  // The last run's length on its thread, and how long the last finish() waited for it (0 when
  // the run was over first, or ran inline), in microseconds of the steady clock: for benches.
  [[nodiscard]] double last_run_us() const { return run_us_; }
  [[nodiscard]] double last_wait_us() const { return wait_us_; }

 private:
  void loop();
  void run_inline(Fn fn, void* ctx);
  Fn fn_ = nullptr;  // under mutex_
  void* ctx_ = nullptr;
  bool threaded_;
  bool running_ = false;  // started and not yet finished (the caller's view)
  std::thread thread_;
  std::mutex mutex_;
  std::condition_variable wake_;
  bool go_ = false, quit_ = false;  // under mutex_
  std::atomic<bool> done_{true};
  double run_us_ = 0.0;   // written by the run's thread before done_, read after it
  double wait_us_ = 0.0;
};

}  // namespace cathbox::tool
