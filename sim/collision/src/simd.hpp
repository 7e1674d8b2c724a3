#pragma once
// Four float lanes through the GCC/Clang vector extension (SSE on x86-64, NEON on ARM), with
// the few helpers the tree needs. Comparisons give all-ones / all-zeros lanes.
#include <cstdint>
#include <cstring>

namespace cathbox::collision::detail {

using v4f = float __attribute__((vector_size(16)));
using v4i = std::int32_t __attribute__((vector_size(16)));

inline v4f splat(float x) { return v4f{x, x, x, x}; }

inline v4f select(v4i mask, v4f yes, v4f no) {
  v4i y;
  v4i n;
  std::memcpy(&y, &yes, sizeof y);
  std::memcpy(&n, &no, sizeof n);
  const v4i r = (y & mask) | (n & ~mask);
  v4f out;
  std::memcpy(&out, &r, sizeof out);
  return out;
}
inline v4f vmin(v4f a, v4f b) { return select(a < b, a, b); }
inline v4f vmax(v4f a, v4f b) { return select(a > b, a, b); }
inline v4f vabs(v4f a) { return vmax(a, -a); }
inline v4f clamp01(v4f a) { return vmin(vmax(a, splat(0.0f)), splat(1.0f)); }

inline v4f load(const float* p) {
  v4f v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

}  // namespace cathbox::collision::detail
