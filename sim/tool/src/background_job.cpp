#include "background_job.hpp"

#include <chrono>
#include <system_error>

namespace cathbox::tool {

namespace {

#if defined(__EMSCRIPTEN__)
constexpr bool kThreadedByDefault = false;  // its thread pool is the session's (host/wasm)
#else
constexpr bool kThreadedByDefault = true;
#endif

constexpr int kSpins = 2048;

inline void pause() {
#if defined(__x86_64__) || defined(__i386__)
  __builtin_ia32_pause();
#else
  std::this_thread::yield();
#endif
}

double us_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - t0).count();
}

double timed(BackgroundJob::Fn fn, void* ctx) {
  const auto t0 = std::chrono::steady_clock::now();
  fn(ctx);
  return us_since(t0);
}

}  // namespace

bool BackgroundJob::threaded_by_default() { return kThreadedByDefault && std::thread::hardware_concurrency() > 1; }

BackgroundJob::BackgroundJob() : threaded_(threaded_by_default()) {}

BackgroundJob::~BackgroundJob() {
  finish();
  if (!thread_.joinable()) return;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    quit_ = true;
  }
  wake_.notify_one();
  thread_.join();
}

void BackgroundJob::set_threaded(bool on) {
  finish();
  threaded_ = on;
}

void BackgroundJob::start(Fn fn, void* ctx) {
  finish();
  if (!threaded_) {
    run_inline(fn, ctx);
    return;
  }
  if (!thread_.joinable()) {
    try {
      thread_ = std::thread([this] { loop(); });
    } catch (const std::system_error&) {  // no thread to be had: the job runs here, as unthreaded
      threaded_ = false;
      run_inline(fn, ctx);
      return;
    }
  }
  done_.store(false, std::memory_order_relaxed);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    fn_ = fn;
    ctx_ = ctx;
    go_ = true;
  }
  wake_.notify_one();
  running_ = true;
}

void BackgroundJob::run_inline(Fn fn, void* ctx) {
  run_us_ = timed(fn, ctx);
  wait_us_ = 0.0;
}

void BackgroundJob::finish() {
  if (!running_) return;
  const auto t0 = std::chrono::steady_clock::now();
  // Spin (~100 us of pauses), then yield: where the job's thread waits for this core (more
  // threads than cores: tests run side by side), it runs in this thread's place.
  for (int i = 0; !done_.load(std::memory_order_acquire); ++i) {
    if (i < kSpins) pause();
    else std::this_thread::yield();
  }
  wait_us_ = us_since(t0);
  running_ = false;
}

void BackgroundJob::loop() {
  for (;;) {
    Fn fn = nullptr;
    void* ctx = nullptr;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      wake_.wait(lock, [this] { return go_ || quit_; });
      if (quit_) return;
      go_ = false;
      fn = fn_;
      ctx = ctx_;
    }
    run_us_ = timed(fn, ctx);
    done_.store(true, std::memory_order_release);
  }
}

}  // namespace cathbox::tool
