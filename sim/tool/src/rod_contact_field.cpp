#include "tool/rod_contact_field.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "collision/segment_pair.hpp"

namespace cathbox::tool {

namespace {

double edge_radius(const Rod& rod, std::size_t e) { return 0.5 * (rod.node_radius_mm(e) + rod.node_radius_mm(e + 1)); }

glm::dvec3 edge_mid(const Rod& rod, std::size_t e) { return 0.5 * (rod.positions()[e] + rod.positions()[e + 1]); }

// Arc length between the middles of two edges of one rod.
double arc_between(const Rod& rod, std::size_t a, std::size_t b) {
  return std::abs(rod.node_from_tip_mm(a) + rod.node_from_tip_mm(a + 1) - rod.node_from_tip_mm(b) -
                  rod.node_from_tip_mm(b + 1)) *
         0.5;
}

// Half the rest length of an edge, with room for a stretched one (edges stretch < 1 %).
double edge_reach(const Rod& rod, std::size_t e) {
  return 0.55 * (rod.node_from_tip_mm(e) - rod.node_from_tip_mm(e + 1)) + edge_radius(rod, e);
}

// Broad phase of a pair: edges whose spheres around their middles (half the length plus the
// radius) are further apart than the margin cannot touch.
bool apart(const glm::dvec3& mid_a, double reach_a, const glm::dvec3& mid_b, double reach_b, double margin) {
  const glm::dvec3 d = mid_a - mid_b;
  const double r = reach_a + reach_b + margin;
  return glm::dot(d, d) > r * r;
}

glm::dvec3 any_perpendicular(const glm::dvec3& t) {
  const glm::dvec3 a = std::abs(t.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 p = a - t * glm::dot(a, t);
  const double l = glm::length(p);
  return l > 1e-12 ? p / l : glm::dvec3(0, 0, 1);
}

}  // namespace

void RodContactField::set_members(std::span<const Member> members) {
  members_.assign(members.begin(), members.end());
  double max_edge = 0.0;
  max_radius_mm_ = 0.0;
  std::size_t items = 0;
  for (const Member& m : members_) {
    const Rod& rod = *m.rod;
    for (std::size_t e = m.edge_first; e < m.edge_last && e + 1 < rod.node_total(); ++e) {
      max_edge = std::max(max_edge, rod.node_from_tip_mm(e) - rod.node_from_tip_mm(e + 1));
      max_radius_mm_ = std::max({max_radius_mm_, rod.node_radius_mm(e), rod.node_radius_mm(e + 1)});
      ++items;
    }
  }
  // Edges that can touch have midpoints within one cell of each other.
  cell_mm_ = std::max(0.05, max_edge + 2.0 * max_radius_mm_ + margin_);
  std::size_t buckets = 64;
  while (buckets < 2 * items) buckets *= 2;
  bucket_mask_ = buckets - 1;
  if (start_.size() < buckets + 1) start_.assign(buckets + 1, 0);
  if (items_.capacity() < items) items_.reserve(items);
  if (bucket_of_item_.capacity() < items) bucket_of_item_.reserve(items);
  if (scratch_.capacity() < items) scratch_.reserve(items);
  if (fill_.capacity() < buckets) fill_.reserve(buckets);
  if (seen_.size() < buckets) seen_.assign(buckets, 0u), query_ = 0;
}

std::size_t RodContactField::bucket_of(std::int64_t x, std::int64_t y, std::int64_t z) const {
  // Teschner et al. (2003) spatial hash.
  const std::uint64_t h = (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
                          (static_cast<std::uint64_t>(z) * 83492791u);
  return static_cast<std::size_t>(h) & bucket_mask_;
}

void RodContactField::build_grid() const {
  const std::size_t buckets = bucket_mask_ + 1;
  std::fill(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(buckets + 1), 0u);
  items_.clear();
  bucket_of_item_.clear();
  for (std::uint32_t mi = 0; mi < members_.size(); ++mi) {
    const Member& m = members_[mi];
    for (std::size_t e = m.edge_first; e < m.edge_last && e + 1 < m.rod->node_total(); ++e) {
      const glm::dvec3 mid = edge_mid(*m.rod, e);
      const glm::dvec3 c = glm::floor(mid / cell_mm_);
      const std::size_t b = bucket_of(static_cast<std::int64_t>(c.x), static_cast<std::int64_t>(c.y),
                                      static_cast<std::int64_t>(c.z));
      bucket_of_item_.push_back(static_cast<std::uint32_t>(b));
      items_.push_back(Item{mi, static_cast<std::uint32_t>(e), mid, edge_reach(*m.rod, e)});
      ++start_[b + 1];
    }
  }
  for (std::size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  // Counting sort of the items by bucket, in place through a second pass.
  scratch_.assign(items_.begin(), items_.end());
  fill_.assign(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(buckets));
  for (std::size_t i = 0; i < scratch_.size(); ++i) items_[fill_[bucket_of_item_[i]]++] = scratch_[i];
}

template <typename Fn>
void RodContactField::for_neighbours(const glm::dvec3& p, Fn&& fn) const {
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
        for (std::uint32_t i = start_[b]; i < start_[b + 1]; ++i) fn(items_[i]);
      }
}

bool RodContactField::excluded(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const {
  if (a.rod == b.rod) {
    if (!a.self) return true;
    const double h = std::max(a.rod->node_from_tip_mm(ea) - a.rod->node_from_tip_mm(ea + 1),
                              a.rod->node_from_tip_mm(eb) - a.rod->node_from_tip_mm(eb + 1));
    return arc_between(*a.rod, ea, eb) < 2.0 * (edge_radius(*a.rod, ea) + edge_radius(*a.rod, eb)) + h;
  }
  // A coil still in (or just leaving) the lumen of the catheter it comes out of.
  if (a.hollow == b.rod && a.rod->node_depth_mm(ea) < a.hollow_depth_mm) return true;
  if (b.hollow == a.rod && b.rod->node_depth_mm(eb) < b.hollow_depth_mm) return true;
  return false;
}

void RodContactField::gather(const Rod& rod, std::vector<EdgeContact>& out) const {
  out.clear();
  const Member* me = nullptr;
  for (const Member& m : members_) {
    if (m.rod == &rod) me = &m;
  }
  if (me == nullptr || members_.empty()) return;
  build_grid();
  const std::span<const glm::dvec3> x = rod.positions();
  for (std::size_t e = me->edge_first; e < me->edge_last && e + 1 < rod.node_total(); ++e) {
    const glm::dvec3& a0 = x[e];
    const glm::dvec3& a1 = x[e + 1];
    const double ra = edge_radius(rod, e);
    const glm::dvec3 mid = 0.5 * (a0 + a1);
    const double reach = edge_reach(rod, e);
    for_neighbours(mid, [&](const Item& item) {
      if (apart(mid, reach, item.mid, item.reach, margin_)) return;
      const Member& other = members_[item.member];
      const std::size_t f = item.edge;
      if (other.rod == &rod && f == e) return;
      if (excluded(*me, e, other, f)) return;
      const glm::dvec3& b0 = other.rod->positions()[f];
      const glm::dvec3& b1 = other.rod->positions()[f + 1];
      const collision::SegmentPair pair = collision::closest_segment_segment(a0, a1, b0, b1);
      const double s = pair.s;
      const double t = pair.t;
      const glm::dvec3 p = a0 + (a1 - a0) * s;
      const glm::dvec3 q = b0 + (b1 - b0) * t;
      const double rr = ra + edge_radius(*other.rod, f);
      const double d = glm::length(p - q);
      if (d >= rr + margin_) return;
      EdgeContact c;
      c.edge = static_cast<std::uint32_t>(e);
      c.s = s;
      c.normal = d > 1e-9 ? (p - q) / d : any_perpendicular(glm::normalize(a1 - a0));
      if (other.rod == &rod) {
        c.offset_mm = glm::dot(c.normal, 0.5 * (p + q)) + 0.5 * rr;  // each side takes half
      } else {
        c.offset_mm = glm::dot(c.normal, q) + rr;
      }
      out.push_back(c);
    });
  }
}

RodContactField::Overlap RodContactField::worst_overlap() const {
  Overlap worst;
  if (members_.empty()) return worst;
  build_grid();
  worst.depth_mm = -1e300;
  for (const Member& me : members_) {
    const Rod& rod = *me.rod;
    for (std::size_t e = me.edge_first; e < me.edge_last && e + 1 < rod.node_total(); ++e) {
      const glm::dvec3& a0 = rod.positions()[e];
      const glm::dvec3& a1 = rod.positions()[e + 1];
      const double ra = edge_radius(rod, e);
      const glm::dvec3 mid = 0.5 * (a0 + a1);
      const double reach = edge_reach(rod, e);
      for_neighbours(mid, [&](const Item& item) {
        const Member& other = members_[item.member];
        const std::size_t f = item.edge;
        if (other.rod == &rod && f == e) return;
        // Pairs apart by more than the margin do not overlap (only the deepest overlap counts).
        if (apart(mid, reach, item.mid, item.reach, 0.0)) return;
        if (excluded(me, e, other, f)) return;
        const glm::dvec3& b0 = other.rod->positions()[f];
        const glm::dvec3& b1 = other.rod->positions()[f + 1];
        const collision::SegmentPair pair = collision::closest_segment_segment(a0, a1, b0, b1);
        const double rb = edge_radius(*other.rod, f);
        const double depth = ra + rb - std::sqrt(pair.distance_sq);
        if (depth > worst.depth_mm) {
          worst.depth_mm = depth;
          worst.diameter_mm = 2.0 * std::min(ra, rb);
        }
      });
    }
  }
  if (worst.depth_mm < -1e299) worst.depth_mm = 0.0;
  return worst;
}

}  // namespace cathbox::tool
