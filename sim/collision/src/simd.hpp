#pragma once
// Four float lanes through the GCC/Clang vector extension (SSE on x86-64, NEON on ARM), with
// the few helpers the tree needs. Comparisons give all-ones / all-zeros lanes.
#include <cstdint>
#include <cstring>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace cathbox::collision::detail {

// Hot kernels are forced inline: GCC at -O2 otherwise leaves some as calls.
#define CATHBOX_COLLISION_INLINE inline __attribute__((always_inline))

// The hot loops are compiled twice on x86-64: for the baseline and for Haswell-class CPUs
// (x86-64-v3: AVX2, FMA), picked at load time by a CPU feature test; elsewhere once.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define CATHBOX_COLLISION_HOT __attribute__((target_clones("arch=x86-64-v3", "default")))
#else
#define CATHBOX_COLLISION_HOT
#endif

using v4f = float __attribute__((vector_size(16)));
using v4i = std::int32_t __attribute__((vector_size(16)));

CATHBOX_COLLISION_INLINE v4f splat(float x) { return v4f{x, x, x, x}; }

CATHBOX_COLLISION_INLINE v4f select(v4i mask, v4f yes, v4f no) {
  v4i y;
  v4i n;
  std::memcpy(&y, &yes, sizeof y);
  std::memcpy(&n, &no, sizeof n);
  const v4i r = (y & mask) | (n & ~mask);
  v4f out;
  std::memcpy(&out, &r, sizeof out);
  return out;
}
#if defined(__SSE2__)
// Native min/max/abs on x86 (min/max return the second operand when either is NaN, as the
// portable select below does).
CATHBOX_COLLISION_INLINE v4f vmin(v4f a, v4f b) { return _mm_min_ps(a, b); }
CATHBOX_COLLISION_INLINE v4f vmax(v4f a, v4f b) { return _mm_max_ps(a, b); }
CATHBOX_COLLISION_INLINE v4f vabs(v4f a) { return _mm_andnot_ps(_mm_set1_ps(-0.0f), a); }
// 1 / a from the 12-bit estimate and one Newton step (~22 bits; 0 gives NaN, as 0 / 0 would).
CATHBOX_COLLISION_INLINE v4f recip(v4f a) {
  const v4f r = _mm_rcp_ps(a);
  return r * (splat(2.0f) - a * r);
}
#else
CATHBOX_COLLISION_INLINE v4f recip(v4f a) { return splat(1.0f) / a; }
CATHBOX_COLLISION_INLINE v4f vmin(v4f a, v4f b) { return select(a < b, a, b); }
CATHBOX_COLLISION_INLINE v4f vmax(v4f a, v4f b) { return select(a > b, a, b); }
CATHBOX_COLLISION_INLINE v4f vabs(v4f a) { return vmax(a, -a); }
#endif
CATHBOX_COLLISION_INLINE v4f clamp01(v4f a) { return vmin(vmax(a, splat(0.0f)), splat(1.0f)); }

CATHBOX_COLLISION_INLINE v4f load(const float* p) {
  v4f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace cathbox::collision::detail
