#pragma once
// Private to the rod-contact field's sources (rod_contact_field.cpp, rod_contact_list.cpp): the
// pair broad phase and the hash grid's look-ups both the list build and the diagnostic's grid
// walk use. Inline: they run per item and pair.
#include <algorithm>
#include <cstddef>
#include <cstdint>

#include <glm/common.hpp>
#include <glm/geometric.hpp>
#include <glm/vec3.hpp>

#include "tool/rod_contact_field.hpp"

namespace cathbox::tool {

namespace rod_contact_detail {

// Broad phase of a pair: edges whose spheres around their middles (half the length plus the
// radius) are further apart than the margin cannot touch.
inline bool apart(const glm::dvec3& mid_a, double reach_a, const glm::dvec3& mid_b, double reach_b, double margin) {
  const glm::dvec3 d = mid_a - mid_b;
  const double r = reach_a + reach_b + margin;
  return glm::dot(d, d) > r * r;
}

// Room for n, the buffer grown geometrically: reserving (or assigning) alone reallocates to
// exactly n whenever n exceeds the capacity, and a list that grows by a few pairs a build then
// takes fresh pages (page faults in the haptic tick) on every build.
template <class Vector>
void reserve_grown(Vector& v, std::size_t n) {
  if (n > v.capacity()) v.reserve(std::max(n, v.capacity() + v.capacity() / 2));
}

// v.assign(n, value) on a geometrically grown buffer.
template <class Vector, class Value>
void assign_grown(Vector& v, std::size_t n, const Value& value) {
  reserve_grown(v, n);
  v.assign(n, value);
}

// At least n elements, those there kept (new ones value-initialised): for arrays every user of
// which writes before it reads, or tells old entries apart.
template <class Vector>
void resize_grown(Vector& v, std::size_t n) {
  reserve_grown(v, n);
  if (v.size() < n) v.resize(n);
}

}  // namespace rod_contact_detail

inline std::size_t RodContactField::bucket_of(std::int64_t x, std::int64_t y, std::int64_t z) const {
  // Teschner et al. (2003) spatial hash.
  const std::uint64_t h = (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
                          (static_cast<std::uint64_t>(z) * 83492791u);
  return static_cast<std::size_t>(h) & bucket_mask_;
}

template <typename Fn>
void RodContactField::for_neighbours(const glm::dvec3& p, Fn&& fn) const {
  for_neighbour_slots(p, [&](std::uint32_t slot) { fn(grid_[slot]); });
}

template <typename Fn>
void RodContactField::for_neighbour_slots(const glm::dvec3& p, Fn&& fn) const {
  const glm::dvec3 c = glm::floor(p / cell_mm_);
  const auto cx = static_cast<std::int64_t>(c.x);
  const auto cy = static_cast<std::int64_t>(c.y);
  const auto cz = static_cast<std::int64_t>(c.z);
  // A bucket that several of the 27 cells hash to is visited once: it carries this query's stamp.
  if (++query_ == 0) {
    std::fill(seen_.begin(), seen_.end(), 0u);
    query_ = 1;
  }
  for (std::int64_t dz = -1; dz <= 1; ++dz)
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        const std::size_t b = bucket_of(cx + dx, cy + dy, cz + dz);
        if (seen_[b] == query_) continue;
        seen_[b] = query_;
        for (std::uint32_t i = start_[b]; i < start_[b + 1]; ++i) fn(i);
      }
}

}  // namespace cathbox::tool
