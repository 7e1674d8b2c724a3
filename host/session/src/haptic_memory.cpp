#include "session/haptic_memory.hpp"

#include <cstdlib>  // defines __GLIBC__ where the C library is glibc

#if defined(__GLIBC__)
#include <malloc.h>
#endif

namespace cathbox::session {

void keep_freed_memory() {
#if defined(__GLIBC__)
  constexpr int kNever = 1 << 30;  // bytes: no block under 1 GB mapped on its own, no top trimmed
  (void)mallopt(M_MMAP_THRESHOLD, kNever);
  (void)mallopt(M_TRIM_THRESHOLD, kNever);
#endif
}

}  // namespace cathbox::session
