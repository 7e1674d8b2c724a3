#pragma once
// Allocator for the tree's big arrays (nodes and triangle blocks: ~110 MB for a 1M-triangle
// mesh). A query touches a few dozen of them at random places, so with 4 KB pages nearly every
// access is also a TLB miss and a page-table walk. Arrays of 2 MB and more are placed on 2 MB
// boundaries and the kernel is asked for transparent huge pages (madvise; a no-op where THP is
// disabled, and nothing but alignment on systems without it). Smaller arrays use operator new.
#include <cstddef>
#include <cstdlib>
#include <new>

#include <sys/mman.h>

namespace cathbox::collision::detail {

inline constexpr std::size_t kHugePageBytes = std::size_t{2} << 20;

template <typename T>
class HugePageAllocator {
 public:
  using value_type = T;

  HugePageAllocator() noexcept = default;
  template <typename U>
  explicit HugePageAllocator(const HugePageAllocator<U>& /*other*/) noexcept {}

  [[nodiscard]] T* allocate(std::size_t n) {
    if (n > static_cast<std::size_t>(-1) / sizeof(T)) throw std::bad_array_new_length();
    const std::size_t bytes = n * sizeof(T);
    if (!huge(bytes)) return static_cast<T*>(::operator new(bytes, std::align_val_t{alignof(T)}));
    void* p = std::aligned_alloc(kHugePageBytes, rounded(bytes));
    if (p == nullptr) throw std::bad_alloc();
#ifdef MADV_HUGEPAGE
    (void)madvise(p, rounded(bytes), MADV_HUGEPAGE);  // advice only: failure leaves 4 KB pages
#endif
    return static_cast<T*>(p);
  }

  void deallocate(T* p, std::size_t n) noexcept {
    const std::size_t bytes = n * sizeof(T);
    if (!huge(bytes)) {
      ::operator delete(p, std::align_val_t{alignof(T)});
    } else {
      std::free(p);
    }
  }

  template <typename U>
  bool operator==(const HugePageAllocator<U>& /*other*/) const noexcept {
    return true;
  }

 private:
  static bool huge(std::size_t bytes) { return bytes >= kHugePageBytes; }
  static std::size_t rounded(std::size_t bytes) { return (bytes + kHugePageBytes - 1) / kHugePageBytes * kHugePageBytes; }
};

}  // namespace cathbox::collision::detail
