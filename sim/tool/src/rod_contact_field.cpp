#include "tool/rod_contact_field.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "collision/segment_pair.hpp"
#include "rod_contact_grid.hpp"

namespace cathbox::tool {

using rod_contact_detail::apart;

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

glm::dvec3 any_perpendicular(const glm::dvec3& t) {
  const glm::dvec3 a = std::abs(t.x) < 0.6 ? glm::dvec3(1, 0, 0) : glm::dvec3(0, 1, 0);
  const glm::dvec3 p = a - t * glm::dot(a, t);
  const double l = glm::length(p);
  return l > 1e-12 ? p / l : glm::dvec3(0, 0, 1);
}

// The same member but for its radius override and where its gathered edges begin among its listed ones.
bool same_member(const RodContactField::Member& a, const RodContactField::Member& b) {
  return a.rod == b.rod && a.list_begin() == b.list_begin() && a.edge_last == b.edge_last && a.self == b.self &&
         a.self_only == b.self_only && a.hollow == b.hollow && a.hollow_depth_mm == b.hollow_depth_mm &&
         a.coil == b.coil && (a.radius_mm > 0.0) == (b.radius_mm > 0.0) && a.frozen == b.frozen;
}

}  // namespace

void RodContactField::set_members(std::span<const Member> members) {
  bool same = members.size() == members_.size();
  for (std::size_t i = 0; same && i < members.size(); ++i) {
    same = same_member(members[i], members_[i]) && members[i].rod->node_total() == node_totals_[i];
  }
  if (same) {
    for (std::size_t i = 0; i < members.size(); ++i) members_[i].edge_first = members[i].edge_first;
    set_radii(members);
    return;
  }
  if (ranges_moved(members)) {
    carry_list_over(members);
    return;
  }
  list_valid_ = false;
  members_.assign(members.begin(), members.end());
  grown_mm_ = 0.0;
  listed_radius_.clear();
  for (const Member& m : members_) listed_radius_.push_back(m.radius_mm);
  list_items();
  ref_end_.assign(2 * items_.size(), glm::dvec3(std::numeric_limits<double>::quiet_NaN()));
  ref_moved_.assign(items_.size(), 0.0);
}

// Items in member order, edges rising, of the present members; the grid and the lists sized
// for them.
void RodContactField::list_items() {
  node_totals_.clear();
  first_item_.clear();
  max_edge_mm_ = 0.0;
  max_radius_mm_ = 0.0;
  max_override_mm_ = 0.0;
  items_.clear();
  balls_.clear();
  for (std::uint32_t mi = 0; mi < members_.size(); ++mi) {
    const Member& m = members_[mi];
    const Rod& rod = *m.rod;
    node_totals_.push_back(rod.node_total());
    first_item_.push_back(static_cast<std::uint32_t>(items_.size()));
    max_override_mm_ = std::max(max_override_mm_, m.radius_mm);
    for (std::size_t e = m.list_begin(); e < m.edge_last && e + 1 < rod.node_total(); ++e) {
      max_edge_mm_ = std::max(max_edge_mm_, rod.node_from_tip_mm(e) - rod.node_from_tip_mm(e + 1));
      if (m.radius_mm > 0.0) {
        items_.push_back(Item{mi, static_cast<std::uint32_t>(e), m.radius_mm});
        balls_.push_back(Ball{glm::dvec3(0.0), edge_reach(rod, e) - edge_radius(rod, e) + m.radius_mm});
        continue;
      }
      max_radius_mm_ = std::max({max_radius_mm_, rod.node_radius_mm(e), rod.node_radius_mm(e + 1)});
      items_.push_back(Item{mi, static_cast<std::uint32_t>(e), edge_radius(rod, e)});
      balls_.push_back(Ball{glm::dvec3(0.0), edge_reach(rod, e)});
    }
  }
  first_item_.push_back(static_cast<std::uint32_t>(items_.size()));
  const std::size_t items = items_.size();
  update_cell();
  std::size_t buckets = 64;
  while (buckets < 2 * items) buckets *= 2;
  bucket_mask_ = buckets - 1;
  if (start_.size() < buckets + 1) start_.assign(buckets + 1, 0);
  if (grid_.capacity() < items) grid_.reserve(items);
  if (grid_balls_.capacity() < items) grid_balls_.reserve(items);
  if (listed_mid_.capacity() < items) listed_mid_.reserve(items);
  if (ref_end_.capacity() < 2 * items) ref_end_.reserve(2 * items);
  spans_.resize(items);  // update_mids sets them
  if (pair_start_.capacity() < items + 1) pair_start_.reserve(items + 1);
  if (bucket_of_item_.capacity() < items) bucket_of_item_.reserve(items);
  if (fill_.capacity() < buckets) fill_.reserve(buckets);
  if (seen_.size() < buckets) seen_.assign(buckets, 0u), query_ = 0;
}

// The same members, rods and radii, with only the edge ranges moved (a coil pushed or drawn a
// node across its catheter's tip or its detachment zone, every 0.5 mm of a push).
bool RodContactField::ranges_moved(std::span<const Member> members) const {
  if (!list_valid_ || members.size() != members_.size()) return false;
  for (std::size_t i = 0; i < members.size(); ++i) {
    Member m = members[i];
    m.edge_first = members_[i].edge_first;
    m.listed_first = members_[i].listed_first;
    m.edge_last = members_[i].edge_last;
    if (!same_member(m, members_[i]) || m.radius_mm != members_[i].radius_mm ||
        m.rod->node_total() != node_totals_[i]) {
      return false;
    }
  }
  return true;
}

// Edges that can be listed have midpoints within one cell of each other: an override touches
// the members' own edges only.
void RodContactField::update_cell() {
  cell_mm_ = std::max(0.05, max_edge_mm_ + max_radius_mm_ + std::max(max_radius_mm_, max_override_mm_) + margin_ + skin_);
}

// A member's radius override changed: its items take it at once. Growth since the list was
// built brings pairs closer like motion: the list covers it (update_mids), a build lists all.
void RodContactField::set_radii(std::span<const Member> members) {
  bool changed = false;
  for (std::size_t mi = 0; mi < members.size(); ++mi) {
    const double r = members[mi].radius_mm;
    if (r == members_[mi].radius_mm) continue;
    changed = true;
    members_[mi].radius_mm = r;
    grown_mm_ = std::max(grown_mm_, r - listed_radius_[mi]);
    const Rod& rod = *members_[mi].rod;
    for (std::uint32_t i = first_item_[mi]; i < first_item_[mi + 1]; ++i) {
      const std::size_t e = items_[i].edge;
      items_[i].radius = r;
      balls_[i].reach = edge_reach(rod, e) - edge_radius(rod, e) + r;
    }
  }
  if (!changed) return;
  max_override_mm_ = 0.0;
  for (const Member& m : members_) max_override_mm_ = std::max(max_override_mm_, m.radius_mm);
  update_cell();
}

bool RodContactField::excluded_always(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const {
  if (a.rod != b.rod) return a.self_only || b.self_only || (a.radius_mm > 0.0 && !b.coil) || (b.radius_mm > 0.0 && !a.coil);
  if (!a.self) return true;
  const double h = std::max(a.rod->node_from_tip_mm(ea) - a.rod->node_from_tip_mm(ea + 1),
                            a.rod->node_from_tip_mm(eb) - a.rod->node_from_tip_mm(eb + 1));
  return arc_between(*a.rod, ea, eb) < 2.0 * (edge_radius(*a.rod, ea) + edge_radius(*a.rod, eb)) + h;
}

bool RodContactField::any_frozen() const {
  return std::any_of(members_.begin(), members_.end(), [](const Member& m) { return m.frozen; });
}

bool RodContactField::excluded_now(const Member& a, std::size_t ea, const Member& b, std::size_t eb) const {
  // A coil still in (or just leaving) the lumen of the catheter it comes out of.
  if (a.hollow == b.rod && a.rod->node_depth_mm(ea) < a.hollow_depth_mm) return true;
  if (b.hollow == a.rod && b.rod->node_depth_mm(eb) < b.hollow_depth_mm) return true;
  return false;
}

template <typename Fn>
void RodContactField::for_candidates(const Member& me, std::uint32_t mi, double margin, Fn&& fn) const {
  // In chunks of an item's list: the broad phase of every slot first, without a branch (which
  // way a packed sac's pairs go is a coin toss: half of a released coil's ~9,000 slots a gather
  // are apart), then the slots it keeps, in their order.
  constexpr std::uint32_t kChunk = 64;
  std::uint32_t near[kChunk];
  for (std::uint32_t i = first_item_[mi] + static_cast<std::uint32_t>(me.edge_first - me.list_begin()); i < first_item_[mi + 1]; ++i) {
    const Item& a = items_[i];
    const Ball ball = balls_[i];
    for (std::uint32_t from = pair_start_[i]; from < pair_start_[i + 1]; from += kChunk) {
      const std::uint32_t to = std::min(from + kChunk, pair_start_[i + 1]);
      std::uint32_t kept = 0;
      for (std::uint32_t p = from; p < to; ++p) {
        const Ball& partner = balls_[pairs_[p]];
        near[kept] = p;
        kept += apart(ball.mid, ball.reach, partner.mid, partner.reach, margin) ? 0u : 1u;
      }
      for (std::uint32_t k = 0; k < kept; ++k) {
        const std::uint32_t p = near[k];
        const Item& b = items_[pairs_[p]];
        const Member& other = members_[b.member];
        if (!gathered(b) || excluded_now(me, a.edge, other, b.edge)) continue;
        fn(a, other, b, p);
      }
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
    // since (each bounded by its drifts then and now and its reference's moves between: Span)
    // cannot be in reach; the segment test would reject it.
    LastGap& last = last_gap_[slot];
    const Span& sa = spans_[static_cast<std::size_t>(&a - items_.data())];
    const Span& sb = spans_[static_cast<std::size_t>(&b - items_.data())];
    if (last.bound_mm - sa.far - sb.far >= rr + margin_ + 1e-9) return;
    const glm::dvec3& a0 = x[e];
    const glm::dvec3& a1 = x[e + 1];
    const glm::dvec3& b0 = other.rod->positions()[f];
    const glm::dvec3& b1 = other.rod->positions()[f + 1];
    const collision::SegmentPair pair = collision::closest_segment_segment(a0, a1, b0, b1);
    ++pair_tests_;
    const double s = pair.s;
    const double t = pair.t;
    const glm::dvec3 p = a0 + (a1 - a0) * s;
    const glm::dvec3 q = b0 + (b1 - b0) * t;
    const double d = glm::length(p - q);
    last.bound_mm = d + sa.near + sb.near;
    if (d >= rr + margin_) return;
    if (side != nullptr) side->contact = static_cast<std::uint32_t>(out.size()), side->t = t;
    EdgeContact c;
    c.edge = static_cast<std::uint32_t>(e);
    c.s = s;
    // A balloon takes the coil's contact law: the two sides push alike.
    if (me.radius_mm > 0.0) c.stiffness_mN_per_mm = other.rod->settings().contact_stiffness_mN_per_mm;
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
  // the solver's work): the pairs come from the grid instead, as they do for a field whose frozen
  // members' pairs are not listed.
  if (update_mids() && !any_frozen()) {
    for (std::uint32_t mi = 0; mi < members_.size(); ++mi) for_candidates(members_[mi], mi, 0.0, pair_depth);
  } else {
    build_grid(false);
    for (std::uint32_t i = 0; i < items_.size(); ++i) {
      const Item& a = items_[i];
      const Member& me = members_[a.member];
      if (!gathered(a)) continue;
      for_neighbours(balls_[i].mid, [&](std::uint32_t j) {
        const Item& b = items_[j];
        const Member& other = members_[b.member];
        if (j == i || !gathered(b) || apart(balls_[i].mid, balls_[i].reach, balls_[j].mid, balls_[j].reach, 0.0)) return;
        if (excluded_always(me, a.edge, other, b.edge) || excluded_now(me, a.edge, other, b.edge)) return;
        pair_depth(a, other, b, 0);
      });
    }
  }
  if (worst.depth_mm < -1e299) worst.depth_mm = 0.0;
  return worst;
}

}  // namespace cathbox::tool
