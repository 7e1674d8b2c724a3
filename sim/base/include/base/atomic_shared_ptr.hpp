#pragma once
// std::atomic<std::shared_ptr<T>> (C++20), or where the library lacks it (libc++ before 18:
// emscripten's, the WebAssembly build) the same load and store made of the C++11 atomic
// shared_ptr functions.
#include <atomic>
#include <memory>
#include <version>

namespace cathbox::base {

#if defined(__cpp_lib_atomic_shared_ptr)
template <class T>
using AtomicSharedPtr = std::atomic<std::shared_ptr<T>>;
#else
template <class T>
class AtomicSharedPtr {
 public:
  void store(std::shared_ptr<T> p, std::memory_order order = std::memory_order_seq_cst) noexcept {
    std::atomic_store_explicit(&p_, std::move(p), order);
  }
  [[nodiscard]] std::shared_ptr<T> load(std::memory_order order = std::memory_order_seq_cst) const noexcept {
    return std::atomic_load_explicit(&p_, order);
  }

 private:
  std::shared_ptr<T> p_;
};
#endif

}  // namespace cathbox::base
