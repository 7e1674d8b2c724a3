#include "tool/rod_contact_field.hpp"

#include <algorithm>
#include <cmath>

#include <glm/geometric.hpp>

#include "collision/segment_pair.hpp"

namespace cathbox::tool {

namespace {

double edge_radius(const Rod& rod, std::size_t e) { return 0.5 * (rod.node_radius_mm(e) + rod.node_radius_mm(e + 1)); }

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

namespace {

bool same_member(const RodContactField::Member& a, const RodContactField::Member& b) {
  return a.rod == b.rod && a.edge_first == b.edge_first && a.edge_last == b.edge_last && a.self == b.self &&
         a.self_only == b.self_only &&
         a.hollow == b.hollow && a.hollow_depth_mm == b.hollow_depth_mm;
}

}  // namespace

void RodContactField::set_members(std::span<const Member> members) {
  bool same = members.size() == members_.size();
  for (std::size_t i = 0; same && i < members.size(); ++i) {
    same = same_member(members[i], members_[i]) && members[i].rod->node_total() == node_totals_[i];
  }
  if (same) return;
  list_valid_ = false;
  members_.assign(members.begin(), members.end());
  node_totals_.clear();
  first_item_.clear();
  double max_edge = 0.0;
  max_radius_mm_ = 0.0;
  items_.clear();
  balls_.clear();
  for (std::uint32_t mi = 0; mi < members_.size(); ++mi) {
    const Member& m = members_[mi];
    const Rod& rod = *m.rod;
    node_totals_.push_back(rod.node_total());
    first_item_.push_back(static_cast<std::uint32_t>(items_.size()));
    for (std::size_t e = m.edge_first; e < m.edge_last && e + 1 < rod.node_total(); ++e) {
      max_edge = std::max(max_edge, rod.node_from_tip_mm(e) - rod.node_from_tip_mm(e + 1));
      max_radius_mm_ = std::max({max_radius_mm_, rod.node_radius_mm(e), rod.node_radius_mm(e + 1)});
      items_.push_back(Item{mi, static_cast<std::uint32_t>(e), edge_radius(rod, e)});
      balls_.push_back(Ball{glm::dvec3(0.0), edge_reach(rod, e)});
    }
  }
  first_item_.push_back(static_cast<std::uint32_t>(items_.size()));
  const std::size_t items = items_.size();
  // Edges that can be listed have midpoints within one cell of each other.
  cell_mm_ = std::max(0.05, max_edge + 2.0 * max_radius_mm_ + margin_ + skin_);
  std::size_t buckets = 64;
  while (buckets < 2 * items) buckets *= 2;
  bucket_mask_ = buckets - 1;
  if (start_.size() < buckets + 1) start_.assign(buckets + 1, 0);
  if (grid_.capacity() < items) grid_.reserve(items);
  if (listed_mid_.capacity() < items) listed_mid_.reserve(items);
  if (listed_end_.capacity() < 2 * items) listed_end_.reserve(2 * items);
  if (pair_start_.capacity() < items + 1) pair_start_.reserve(items + 1);
  if (bucket_of_item_.capacity() < items) bucket_of_item_.reserve(items);
  if (fill_.capacity() < buckets) fill_.reserve(buckets);
  if (seen_.size() < buckets) seen_.assign(buckets, 0u), query_ = 0;
}

std::size_t RodContactField::bucket_of(std::int64_t x, std::int64_t y, std::int64_t z) const {
  // Teschner et al. (2003) spatial hash.
  const std::uint64_t h = (static_cast<std::uint64_t>(x) * 73856093u) ^ (static_cast<std::uint64_t>(y) * 19349663u) ^
                          (static_cast<std::uint64_t>(z) * 83492791u);
  return static_cast<std::size_t>(h) & bucket_mask_;
}

bool RodContactField::update_mids() const {
  // An edge's middle that moved less than half the skin since the list was built keeps every
  // pair within the contact reach among the listed ones (two middles close by at most the skin).
  const double limit_sq = 0.25 * skin_ * skin_;
  bool covered = list_valid_;
  for (std::size_t i = 0; i < items_.size(); ++i) {
    Item& item = items_[i];
    const std::span<const glm::dvec3> x = members_[item.member].rod->positions();
    const glm::dvec3& p0 = x[item.edge];
    const glm::dvec3& p1 = x[item.edge + 1];
    balls_[i].mid = 0.5 * (p0 + p1);
    if (covered) {
      const glm::dvec3 d = balls_[i].mid - listed_mid_[i];
      covered = glm::dot(d, d) <= limit_sq;
      const glm::dvec3 d0 = p0 - listed_end_[2 * i];
      const glm::dvec3 d1 = p1 - listed_end_[2 * i + 1];
      item.drift = std::sqrt(std::max(glm::dot(d0, d0), glm::dot(d1, d1)));
    }
  }
  return covered;
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
        for (std::uint32_t i = start_[b]; i < start_[b + 1]; ++i) fn(grid_[i]);
      }
}

void RodContactField::build_grid(bool listed) const {
  const std::size_t buckets = bucket_mask_ + 1;
  const std::size_t n = items_.size();
  std::fill(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(buckets + 1), 0u);
  bucket_of_item_.clear();
  for (std::size_t i = 0; i < n; ++i) {
    const glm::dvec3 c = glm::floor((listed ? listed_mid_[i] : balls_[i].mid) / cell_mm_);
    const std::size_t b = bucket_of(static_cast<std::int64_t>(c.x), static_cast<std::int64_t>(c.y),
                                    static_cast<std::int64_t>(c.z));
    bucket_of_item_.push_back(static_cast<std::uint32_t>(b));
    ++start_[b + 1];
  }
  for (std::size_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  // Counting sort of the item indices by bucket.
  fill_.assign(start_.begin(), start_.begin() + static_cast<std::ptrdiff_t>(buckets));
  grid_.resize(n);
  for (std::uint32_t i = 0; i < n; ++i) grid_[fill_[bucket_of_item_[i]]++] = i;
}

// Items whose middle left its listed place by more than a quarter of the skin (every item when
// the members changed) are listed again where they are now; the ends' drifts are set afresh.
bool RodContactField::relist_moved() const {
  const std::size_t n = items_.size();
  const bool partial = list_valid_ && listed_mid_.size() == n;
  listed_mid_.resize(n);
  listed_end_.resize(2 * n);
  relisted_.assign(n, 1);
  const double keep_sq = 0.0625 * skin_ * skin_;
  for (std::size_t i = 0; i < n; ++i) {
    Item& item = items_[i];
    const std::span<const glm::dvec3> x = members_[item.member].rod->positions();
    const glm::dvec3 d = balls_[i].mid - listed_mid_[i];
    if (partial && glm::dot(d, d) <= keep_sq) {
      relisted_[i] = 0;
      item.drift = std::sqrt(std::max(glm::dot(x[item.edge] - listed_end_[2 * i], x[item.edge] - listed_end_[2 * i]),
                                      glm::dot(x[item.edge + 1] - listed_end_[2 * i + 1],
                                               x[item.edge + 1] - listed_end_[2 * i + 1])));
      continue;
    }
    listed_mid_[i] = balls_[i].mid;
    listed_end_[2 * i] = x[item.edge];
    listed_end_[2 * i + 1] = x[item.edge + 1];
    item.drift = 0.0;
  }
  return partial;
}

void RodContactField::build_list() const {
  ++list_builds_;
  const std::size_t n = items_.size();
  relisted_all_ = !relist_moved();
  if (relisted_all_) halves_.clear();  // the members changed: no pair is kept
  build_grid(true);
  // Each pair is classified on the two items' listed middles: a pair left out is further apart
  // than the reach plus the margin and the skin there, and each item stays within half the skin
  // of its listed middle until the next build, so it cannot come into reach. Pairs of two items
  // not listed again are kept from the last build; a relisted item's pairs are found afresh:
  // with higher items (`fresh_`, in rising order per item, as the lists need them) and with
  // lower items kept in place (`lower_`, sorted after).
  std::erase_if(halves_, [&](const auto& h) { return relisted_[h.first] != 0 || relisted_[h.second] != 0; });
  fresh_.clear();
  lower_.clear();
  for (std::uint32_t i = 0; i < n; ++i) {
    if (relisted_[i] == 0) continue;
    const std::size_t from = fresh_.size();
    const Item& a = items_[i];
    const Member& ma = members_[a.member];
    for_neighbours(listed_mid_[i], [&](std::uint32_t j) {
      if (j == i || (j < i && relisted_[j] != 0)) return;  // the lower relisted item found it
      const Item& b = items_[j];
      if (apart(listed_mid_[i], balls_[i].reach, listed_mid_[j], balls_[j].reach, margin_ + skin_)) return;
      if (excluded_always(ma, a.edge, members_[b.member], b.edge)) return;
      if (j > i) fresh_.push_back({i, j});
      else lower_.push_back({j, i});
    });
    std::sort(fresh_.begin() + static_cast<std::ptrdiff_t>(from), fresh_.end());
  }
  std::sort(lower_.begin(), lower_.end());
  merged_.clear();
  std::merge(halves_.begin(), halves_.end(), fresh_.begin(), fresh_.end(), std::back_inserter(merged_));
  halves_.clear();
  std::merge(merged_.begin(), merged_.end(), lower_.begin(), lower_.end(), std::back_inserter(halves_));
  const bool partial = !relisted_all_;
  if (partial) {
    kept_start_.swap(pair_start_);
    kept_pairs_.swap(pairs_);
    kept_gap_.swap(last_gap_);
  }
  pair_start_.assign(n + 1, 0u);
  for (const auto& [i, j] : halves_) ++pair_start_[i + 1], ++pair_start_[j + 1];
  for (std::size_t i = 0; i < n; ++i) pair_start_[i + 1] += pair_start_[i];
  // Item k receives its lower partners (while they are filled, in rising order) before its own
  // higher ones: each list comes out sorted.
  pairs_.resize(pair_start_[n]);
  mirror_.resize(pair_start_[n]);
  next_.assign(pair_start_.begin(), pair_start_.end() - 1);
  for (const auto& [i, j] : halves_) {
    mirror_[next_[i]] = next_[j];
    mirror_[next_[j]] = next_[i];
    pairs_[next_[i]++] = j;
    pairs_[next_[j]++] = i;
  }
  last_gap_.assign(pairs_.size(), LastGap{});
  if (partial) keep_last_gaps();
  lower_side_.assign(pairs_.size(), LowerSide{});
  gathers_ = 0;
  list_valid_ = true;
}

// A pair of two items not listed again keeps its last tested gap: both items' drifts are still
// measured from the same listed ends, so the gather's cull stays a bound (without it the gathers
// after a build tested every listed pair again). Both lists of an item are sorted: one merge walk.
void RodContactField::keep_last_gaps() const {
  const std::size_t n = items_.size();
  for (std::size_t i = 0; i < n && i + 1 < kept_start_.size(); ++i) {
    if (relisted_[i] != 0) continue;
    std::uint32_t o = kept_start_[i];
    const std::uint32_t o_end = kept_start_[i + 1];
    for (std::uint32_t p = pair_start_[i]; p < pair_start_[i + 1] && o < o_end; ++p) {
      const std::uint32_t j = pairs_[p];
      while (o < o_end && kept_pairs_[o] < j) ++o;
      if (o < o_end && kept_pairs_[o] == j && relisted_[j] == 0) last_gap_[p] = kept_gap_[o];
    }
  }
}

bool RodContactField::excluded_always(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const {
  if (a.rod != b.rod) return a.self_only || b.self_only;
  if (!a.self) return true;
  const double h = std::max(a.rod->node_from_tip_mm(ea) - a.rod->node_from_tip_mm(ea + 1),
                            a.rod->node_from_tip_mm(eb) - a.rod->node_from_tip_mm(eb + 1));
  return arc_between(*a.rod, ea, eb) < 2.0 * (edge_radius(*a.rod, ea) + edge_radius(*a.rod, eb)) + h;
}

bool RodContactField::excluded_now(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const {
  // A coil still in (or just leaving) the lumen of the catheter it comes out of.
  if (a.hollow == b.rod && a.rod->node_depth_mm(ea) < a.hollow_depth_mm) return true;
  if (b.hollow == a.rod && b.rod->node_depth_mm(eb) < b.hollow_depth_mm) return true;
  return false;
}

template <typename Fn>
void RodContactField::for_candidates(const Member& me, std::uint32_t mi, double margin, Fn&& fn) const {
  for (std::uint32_t i = first_item_[mi]; i < first_item_[mi + 1]; ++i) {
    const Item& a = items_[i];
    const Ball ball = balls_[i];
    for (std::uint32_t p = pair_start_[i]; p < pair_start_[i + 1]; ++p) {
      const std::uint32_t j = pairs_[p];
      if (apart(ball.mid, ball.reach, balls_[j].mid, balls_[j].reach, margin)) continue;
      const Item& b = items_[j];
      const Member& other = members_[b.member];
      if (excluded_now(me, a.edge, other, b.edge)) continue;
      fn(a, other, b, p);
    }
  }
}

void RodContactField::gather(const Rod& rod, std::vector<EdgeContact>& out) const {
  out.clear();
  std::uint32_t mi = 0;
  while (mi < members_.size() && members_[mi].rod != &rod) ++mi;
  if (mi == members_.size()) return;
  ++gather_calls_;
  if (!update_mids()) build_list();
  if (++gathers_ == 0) {
    for (LowerSide& side : lower_side_) side.stamp = 0;
    gathers_ = 1;
  }
  const Member& me = members_[mi];
  const std::span<const glm::dvec3> x = rod.positions();
  for_candidates(me, mi, margin_, [&](const Item& a, const Member& other, const Item& b, std::uint32_t slot) {
    const std::size_t e = a.edge;
    const std::size_t f = b.edge;
    const double rr = a.radius + b.radius;
    // Two edges of this rod: the pair passed the same cull from its lower edge earlier in this
    // gather (the cull is symmetric), whose test gives this side too.
    const bool self = other.rod == &rod;
    const bool upper = self && &b < &a;
    if (upper && lower_side_[mirror_[slot]].stamp == gathers_) {
      const LowerSide& lower = lower_side_[mirror_[slot]];
      if (lower.contact == kNoContact) return;
      EdgeContact c;
      c.edge = static_cast<std::uint32_t>(e);
      c.s = lower.t;
      c.normal = -out[lower.contact].normal;
      c.offset_mm = rr - out[lower.contact].offset_mm;  // the same plane through the gap's middle
      out.push_back(c);
      return;
    }
    LowerSide* side = self && !upper ? &lower_side_[slot] : nullptr;
    if (side != nullptr) *side = LowerSide{gathers_, kNoContact, 0.0};
    // Two segments whose ends moved by at most m and n come no closer than their distance
    // less m + n: a pair that was far enough apart when last tested and has not moved enough
    // since (both measured from the listed positions) cannot be in reach; the segment test
    // would reject it.
    LastGap& last = last_gap_[slot];
    if (last.gap_mm - last.drift_mm - a.drift - b.drift >= rr + margin_ + 1e-9) return;
    const glm::dvec3& a0 = x[e];
    const glm::dvec3& a1 = x[e + 1];
    const glm::dvec3& b0 = other.rod->positions()[f];
    const glm::dvec3& b1 = other.rod->positions()[f + 1];
    const collision::SegmentPair pair = collision::closest_segment_segment(a0, a1, b0, b1);
    const double s = pair.s;
    const double t = pair.t;
    const glm::dvec3 p = a0 + (a1 - a0) * s;
    const glm::dvec3 q = b0 + (b1 - b0) * t;
    const double d = glm::length(p - q);
    last.gap_mm = d;
    last.drift_mm = a.drift + b.drift;
    if (d >= rr + margin_) return;
    if (side != nullptr) side->contact = static_cast<std::uint32_t>(out.size()), side->t = t;
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

RodContactField::Overlap RodContactField::worst_overlap() const {
  Overlap worst;
  if (members_.empty()) return worst;
  worst.depth_mm = -1e300;
  const auto pair_depth = [&](const Item& a, const Member& other, const Item& b, std::uint32_t /*slot*/) {
    const Rod& rod = *members_[a.member].rod;
    const collision::SegmentPair pair =
        collision::closest_segment_segment(rod.positions()[a.edge], rod.positions()[a.edge + 1],
                                           other.rod->positions()[b.edge], other.rod->positions()[b.edge + 1]);
    const double ra = a.radius;
    const double rb = b.radius;
    const double depth = ra + rb - std::sqrt(pair.distance_sq);
    if (depth > worst.depth_mm) {
      worst.depth_mm = depth;
      worst.diameter_mm = 2.0 * std::min(ra, rb);
    }
  };
  // Pairs apart by more than the contact distance do not overlap. A list that no longer covers
  // the present positions is left for the next gather to rebuild (a diagnostic does not move
  // the solver's work): the pairs come from the grid instead.
  if (update_mids()) {
    for (std::uint32_t mi = 0; mi < members_.size(); ++mi) for_candidates(members_[mi], mi, 0.0, pair_depth);
  } else {
    build_grid(false);
    for (std::uint32_t i = 0; i < items_.size(); ++i) {
      const Item& a = items_[i];
      const Member& me = members_[a.member];
      for_neighbours(balls_[i].mid, [&](std::uint32_t j) {
        const Item& b = items_[j];
        const Member& other = members_[b.member];
        if (j == i || apart(balls_[i].mid, balls_[i].reach, balls_[j].mid, balls_[j].reach, 0.0)) return;
        if (excluded_always(me, a.edge, other, b.edge) || excluded_now(me, a.edge, other, b.edge)) return;
        pair_depth(a, other, b, 0);
      });
    }
  }
  if (worst.depth_mm < -1e299) worst.depth_mm = 0.0;
  return worst;
}

}  // namespace cathbox::tool
