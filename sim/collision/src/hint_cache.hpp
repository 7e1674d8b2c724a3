#pragma once
// The per-node cut of the tree a QueryHint keeps (HintCache, QueryHint's friend): refilled around
// a point when the point moves out of it, and the leaves near a point found from it.
// Part of obb_tree.cpp's translation unit (see query_basics.hpp).
#include "collision/query_hint.hpp"
#include "nearest_search.hpp"

namespace cathbox::collision {

class HintCache {
 public:
  static_assert(QueryHint::kBoxRows == detail::kBoxRows);
  static_assert(QueryHint::kSlots % 4 == 0);

  static bool usable(const QueryHint& h, const TreeData& d) { return h.valid() && h.tree_id_ == d.id; }
  static double moved(const QueryHint& h, const glm::dvec3& p) {
    return glm::length(p - glm::dvec3{h.origin_mm_[0], h.origin_mm_[1], h.origin_mm_[2]});
  }
  static void count_hit(QueryHint& h) { ++h.hits_; }

  // Takes a cut of the tree around p: at most kSlots subtrees that together hold every triangle
  // within `radius` of p (by the float box bounds, which never exceed the true distance). Boxes
  // beyond the radius are dropped as they are met; the nearest subtrees (largest first among
  // those containing p) are opened until the cut is full.
  CATHBOX_COLLISION_HOT static void refill(const TreeData& d, const glm::dvec3& p, double radius, QueryHint& h) {
    ++h.refills_;
    const PointLanes lanes = lanes_of(p);
    const float limit = threshold_sq(radius, slack_for(d, p));
    struct Entry {
      float lb;
      float size;
      std::int32_t slot;
      std::int32_t parent;  // the wide node whose lane holds the box
      int lane;
      bool openable;
    };
    constexpr int kCap = QueryHint::kSlots;
    Entry e[kCap];  // the cut
    // Children of wide node `parent` that may hold a triangle within the radius.
    auto children = [&](std::int32_t parent, Entry (&out)[4]) {
      const detail::WideNode& node = d.nodes[static_cast<std::size_t>(parent)];
      float v[4];
      const v4f lb = detail::box_distance_sq(node.boxes.row, lanes);
      std::memcpy(v, &lb, sizeof v);
      int k = 0;
      for (int i = 0; i < 4; ++i) {
        const std::int32_t slot = node.child[i];
        if (slot == detail::kEmptySlot || !(v[i] <= limit)) continue;
        const float size = node.boxes.row[12][i] + node.boxes.row[13][i] + node.boxes.row[14][i];
        out[k++] = {v[i], size, slot, parent, i, !detail::is_leaf(slot)};
      }
      return k;
    };
    // Subtrees still to open, nearest first (a binary heap), and the cut's final slots.
    Entry open[kCap];
    int n_open = 0;
    int n = 0;
    auto later = [](const Entry& x, const Entry& y) { return x.lb > y.lb || (x.lb == y.lb && x.size < y.size); };
    auto add = [&](const Entry& x) {
      if (x.openable) {
        open[n_open++] = x;
        std::push_heap(open, open + n_open, later);
      } else {
        e[n++] = x;
      }
    };
    Entry kids[4];
    const int roots = children(0, kids);
    for (int i = 0; i < roots; ++i) add(kids[i]);
    while (n_open > 0) {
      std::pop_heap(open, open + n_open, later);
      const Entry top = open[--n_open];
      const int k = children(top.slot, kids);
      if (n + n_open + k > kCap) {
        e[n++] = top;  // no room to open it: it stays whole in the cut
        continue;
      }
      for (int i = 0; i < k; ++i) add(kids[i]);
    }
    std::sort(e, e + n, [](const Entry& x, const Entry& y) { return x.lb < y.lb; });
    h.radius_mm_ = limit == kInfF ? kInf : radius;
    h.clear_mm_ = 0.0;
    h.origin_mm_[0] = p.x;
    h.origin_mm_[1] = p.y;
    h.origin_mm_[2] = p.z;
    h.tree_id_ = d.id;
    h.count_ = n;
    for (int j = 0; j < (n + 3) / 4 * 4; ++j) {
      float(*group)[4] = h.boxes_[j / 4];
      const int lane = j % 4;
      if (j < n) {
        const detail::WideNode& parent = d.nodes[static_cast<std::size_t>(e[j].parent)];
        for (int r = 0; r < detail::kBoxRows; ++r) group[r][lane] = parent.boxes.row[r][e[j].lane];
        h.slot_[j] = e[j].slot;
        if (lane == 0) h.group_min_mm_[j / 4] = std::sqrt(e[j].lb);
      } else {
        for (int r = 0; r < detail::kBoxRows; ++r) group[r][lane] = 0.0f;
        h.slot_[j] = detail::kEmptySlot;
      }
    }
  }

  // Calls push(bound, slot) for the cut's slots whose boxes lie within sqrt(thresh) of p and
  // starts loading them. Groups are nearest to the origin first, so once a group's nearest box
  // was farther from the origin than sqrt(thresh) + the distance moved, the rest are out of reach
  // too. `thresh` is read per group: a caller's search may tighten it meanwhile.
  template <typename Push>
  CATHBOX_COLLISION_INLINE static void slots_near(const QueryHint& h, const TreeData& d, const PointLanes& p,
                                                  double moved, float slack, const float& thresh, Push&& push) {
    for (int g = 0; 4 * g < h.count_; ++g) {
      const double reach = static_cast<double>(h.group_min_mm_[g]) - static_cast<double>(slack) - moved;
      if (reach > 0.0 && reach * reach > static_cast<double>(thresh)) break;
      float v[4];
      const v4f lb = detail::box_distance_sq(h.boxes_[g], p);
      std::memcpy(v, &lb, sizeof v);
      for (int i = 0; i < 4; ++i) {
        const std::int32_t slot = h.slot_[4 * g + i];
        if (slot == detail::kEmptySlot || !(v[i] <= thresh)) continue;
        if (detail::is_leaf(slot)) {
          prefetch(d.blocks[static_cast<std::size_t>(detail::leaf_block(slot))]);
        } else {
          prefetch(d.nodes[static_cast<std::size_t>(slot)]);
        }
        push(v[i], slot);
      }
    }
  }

  // Nearest triangle below the cut, starting with the leaf of the previous answer.
  CATHBOX_COLLISION_HOT static void search(const QueryHint& h, Nearest& s, double moved) {
    if (h.seed_block_ >= 0 && static_cast<std::size_t>(h.seed_block_) < s.d.blocks.size()) {
      s.visit_block(h.seed_block_);
      s.visited = h.seed_block_;
    }
    PendingBoxes pending;
    slots_near(h, s.d, s.lanes, moved, s.slack, s.thresh, [&](float lb, std::int32_t slot) { pending.push(lb, slot); });
    best_first(s, pending);
  }

  // After an exact search at distance `moved` from the origin: the answer's leaf seeds the next
  // search, and no triangle is nearer to the origin than the answer's distance (or the query's
  // limit, when nothing was within it) minus `moved`.
  static void remember(QueryHint& h, const Nearest& s, double moved) {
    h.seed_block_ = s.best_block ? static_cast<std::int32_t>(s.best_block - s.d.blocks.data()) : -1;
    const double bound = s.bound();
    if (std::isfinite(bound)) h.clear_mm_ = std::max(h.clear_mm_, bound - moved);
  }

  // True when the hint proves that no triangle lies within `reach` of a point `moved` from the
  // origin (the margin absorbs rounding in the distances).
  static bool clear_of(const QueryHint& h, double moved, double reach) {
    return h.clear_mm_ - moved > reach * (1.0 + 1e-12) + 1e-12;
  }

  // Calls fn(block) for every leaf below the cut whose box lies within sqrt(thresh) of p.
  // `delta`: the distance of p from the hint's origin.
  template <typename Fn>
  static void for_each_leaf_near(const QueryHint& h, const TreeData& d, const glm::dvec3& p, double delta, float thresh,
                                 Fn&& fn) {
    const PointLanes lanes = lanes_of(p);
    std::int32_t stack[kStackSize];
    int sp = 0;
    slots_near(h, d, lanes, delta, slack_for(d, p), thresh, [&](float, std::int32_t slot) { stack[sp++] = slot; });
    for_each_leaf_below(d, lanes, thresh, stack, sp, fn);
  }
};

}  // namespace cathbox::collision
