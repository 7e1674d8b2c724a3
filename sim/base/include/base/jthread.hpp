#pragma once
// std::jthread and std::stop_token, as the session's threads use them (a thread that is asked to
// stop and joined when destroyed). libc++ before 18 (emscripten's, the WebAssembly build) has
// neither, so there the same few members are made from std::thread and an atomic flag: a stop
// token that can only be asked whether a stop was requested (no callbacks, no waits on it).
#include <version>

#if defined(__cpp_lib_jthread)
#include <stop_token>
#include <thread>

namespace cathbox::base {
using std::jthread;
using std::stop_token;
}  // namespace cathbox::base

#else
#include <atomic>
#include <memory>
#include <thread>
#include <type_traits>
#include <utility>

namespace cathbox::base {

class stop_token {
 public:
  stop_token() = default;
  explicit stop_token(std::shared_ptr<const std::atomic<bool>> flag) : flag_(std::move(flag)) {}
  [[nodiscard]] bool stop_requested() const noexcept { return flag_ && flag_->load(std::memory_order_acquire); }
  [[nodiscard]] bool stop_possible() const noexcept { return flag_ != nullptr; }

 private:
  std::shared_ptr<const std::atomic<bool>> flag_;
};

class jthread {
 public:
  jthread() = default;
  template <class F>
    requires std::is_invocable_v<F, stop_token>
  explicit jthread(F&& f)
      : flag_(std::make_shared<std::atomic<bool>>(false)),
        thread_([fn = std::forward<F>(f), token = stop_token(flag_)]() mutable { fn(std::move(token)); }) {}
  ~jthread() { reset(); }
  jthread(const jthread&) = delete;
  jthread& operator=(const jthread&) = delete;
  jthread(jthread&& other) noexcept = default;
  jthread& operator=(jthread&& other) noexcept {
    if (this != &other) {
      reset();
      flag_ = std::move(other.flag_);
      thread_ = std::move(other.thread_);
    }
    return *this;
  }

  bool request_stop() noexcept {
    if (!flag_) return false;
    return !flag_->exchange(true, std::memory_order_acq_rel);
  }
  [[nodiscard]] bool joinable() const noexcept { return thread_.joinable(); }
  void join() { thread_.join(); }

 private:
  void reset() {
    if (thread_.joinable()) {
      request_stop();
      thread_.join();
    }
  }
  std::shared_ptr<std::atomic<bool>> flag_;
  std::thread thread_;
};

}  // namespace cathbox::base
#endif
