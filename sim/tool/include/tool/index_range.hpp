#pragma once
// The indices [lo, hi) an array may hold non-zero entries at: per-node loads and stiffness
// additions touch a few hundred nodes of tools thousands of nodes long, so clearing and
// scanning only this range keeps the per-step cost with the inserted part.
#include <algorithm>
#include <cstddef>
#include <limits>

namespace cathbox::tool {

struct IndexRange {
  std::size_t lo = std::numeric_limits<std::size_t>::max();
  std::size_t hi = 0;

  void add(std::size_t k) {
    lo = std::min(lo, k);
    hi = std::max(hi, k + 1);
  }
  void clear() { *this = IndexRange{}; }
  // The range within [0, size).
  [[nodiscard]] std::size_t begin_in(std::size_t size) const { return std::min(lo, size); }
  [[nodiscard]] std::size_t end_in(std::size_t size) const { return std::max(begin_in(size), std::min(hi, size)); }
};

}  // namespace cathbox::tool
