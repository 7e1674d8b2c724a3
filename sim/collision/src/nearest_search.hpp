#pragma once
// The nearest triangle to a point (closest_point, signed_distance, contains): a best-first search
// of the tree on float bounds, the candidates then measured exactly; and the walk over the leaves
// near a point the contact queries use.
// Part of obb_tree.cpp's translation unit (see query_basics.hpp).
#include "query_basics.hpp"

namespace cathbox::collision {

namespace {

// ---- nearest triangle ------------------------------------------------------------------------

// Nearest triangle in two stages: float brackets of every triangle met give a shrinking upper
// bound that prunes the search and a short list of candidates; the candidates are then measured
// exactly, nearest first, until the next one cannot be closer.
struct Nearest {
  static constexpr int kPending = 48;

  Nearest(const TreeData& data, const glm::dvec3& point, double max_distance)
      : d(data), p(point), lanes(lanes_of(point)), slack(slack_for(data, point)), max_d(max_distance),
        best_sq(max_distance < 1e18 ? max_distance * max_distance : kInf) {
    exact_thresh = threshold_sq(max_distance, slack);
    thresh = exact_thresh;
  }
  CATHBOX_COLLISION_INLINE void consider(const detail::TriangleBlock& b, int lane) {
    glm::dvec3 ta, tb, tc;
    detail::block_corners(b, lane, ta, tb, tc);
    const detail::PointOnTriangle q = detail::closest_on_triangle(p, ta, tb, tc);
    const glm::dvec3 diff = p - q.point;
    const double dsq = glm::dot(diff, diff);
    // A tie (two faces sharing the nearest edge or vertex) goes to the lower face index: the
    // visiting order follows float bounds, which differ between builds (the reciprocal
    // estimate and the fused clones on x86, a division in WebAssembly); the answer must not.
    const std::int32_t f = b.face[lane];
    if (dsq < best_sq || (face < 0 && dsq <= best_sq) || (dsq == best_sq && f < face)) {
      best_sq = dsq;
      best_point = q;
      best_block = &b;
      face = f;
      // The block's own unit normal serves a face-interior point (no lookup); slivers store 0.
      best_face_normal = block_normal(b, lane);
      exact_thresh = threshold_sq(std::sqrt(best_sq), slack);
      thresh = std::min(thresh, exact_thresh);
    }
  }
  CATHBOX_COLLISION_INLINE void visit_block(std::int32_t block) {
    if (block == visited) return;
    const detail::TriangleBlock& b = d.blocks[static_cast<std::size_t>(block)];
    const detail::DistanceBracket bracket = detail::triangle_distance_sq(b, lanes);
    float lo[4];
    float hi[4];
    std::memcpy(lo, &bracket.lower, sizeof lo);
    std::memcpy(hi, &bracket.upper, sizeof hi);
    const float hmin = std::min(std::min(hi[0], hi[1]), std::min(hi[2], hi[3]));
    if (hmin < upper_sq) {
      upper_sq = hmin;
      thresh = std::min(exact_thresh, threshold_sq(std::sqrt(static_cast<double>(hmin)), 2.0f * slack));
    }
    for (int i = 0; i < 4; ++i) {
      if (lo[i] > thresh || b.face[i] < 0) continue;
      if (pending_count == kPending) resolve();
      pending[pending_count++] = {lo[i], i, &b};
    }
  }
  // Measures the candidates exactly, nearest first.
  void resolve() {
    for (int i = 1; i < pending_count; ++i) {
      const Pending x = pending[i];
      int j = i;
      for (; j > 0 && pending[j - 1].lower > x.lower; --j) pending[j] = pending[j - 1];
      pending[j] = x;
    }
    for (int i = 0; i < pending_count; ++i) {
      if (pending[i].lower > thresh) break;
      consider(*pending[i].block, pending[i].lane);
    }
    pending_count = 0;
  }
  [[nodiscard]] double bound() const { return face >= 0 ? std::sqrt(best_sq) : max_d; }

  struct Pending {
    float lower;
    int lane;
    const detail::TriangleBlock* block;
  };

  const TreeData& d;
  glm::dvec3 p;
  PointLanes lanes;
  float slack;
  double max_d;
  double best_sq;
  float exact_thresh;  // from the exact best (or the maximum distance)
  float thresh;        // also from the smallest float upper bound
  float upper_sq = kInfF;
  std::int32_t face = -1;
  std::int32_t visited = -1;  // a block measured up front (a hint's seed), not to be measured again
  detail::PointOnTriangle best_point;
  const detail::TriangleBlock* best_block = nullptr;
  glm::dvec3 best_face_normal{0.0};
  Pending pending[kPending];
  int pending_count = 0;
};

// Boxes waiting in a best-first walk, in no order: the nearest is found by a branch-free scan
// (the list stays short, and this beats a binary heap's unpredictable branches).
class PendingBoxes {
 public:
  static constexpr int kCapacity = 256;
  void push(float lb, std::int32_t slot) {
    lb_[size_] = lb;
    slot_[size_++] = slot;
  }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  [[nodiscard]] bool has_room() const { return size_ + 4 <= kCapacity; }
  // Index of the nearest pending box; its bound in `lb`.
  [[nodiscard]] int nearest(float& lb) const {
    int best = 0;
    float best_lb = lb_[0];
    for (int i = 1; i < size_; ++i) {
      const bool nearer = lb_[i] < best_lb;
      best_lb = nearer ? lb_[i] : best_lb;
      best = nearer ? i : best;
    }
    lb = best_lb;
    return best;
  }
  std::int32_t take(int i) {
    const std::int32_t slot = slot_[i];
    --size_;
    lb_[i] = lb_[size_];
    slot_[i] = slot_[size_];
    return slot;
  }

 private:
  float lb_[kCapacity];
  std::int32_t slot_[kCapacity];
  int size_ = 0;
};

// Queues the children of node n whose box bound passes keep(bound), and starts loading them.
template <typename List, typename Keep>
CATHBOX_COLLISION_INLINE void push_children(const TreeData& d, const detail::WideNode& n, const PointLanes& p,
                                            List& pending, Keep&& keep) {
  const v4f lb = detail::box_distance_sq(n.boxes.row, p);
  float v[4];
  std::memcpy(v, &lb, sizeof v);
  for (int i = 0; i < 4; ++i) {
    const std::int32_t slot = n.child[i];
    if (slot == detail::kEmptySlot || !keep(v[i])) continue;
    if (detail::is_leaf(slot)) {
      prefetch(d.blocks[static_cast<std::size_t>(detail::leaf_block(slot))]);
    } else {
      prefetch(d.nodes[static_cast<std::size_t>(slot)]);
    }
    pending.push(v[i], slot);
  }
}

// Depth-first search below `root`, nearest child first (the fallback of the best-first search).
void search_subtree(Nearest& s, std::int32_t root) {
  const TreeData& d = s.d;
  std::int32_t stack[kStackSize];
  float stack_lb[kStackSize];
  int sp = 0;
  stack[sp] = root;
  stack_lb[sp++] = 0.0f;
  while (sp > 0) {
    --sp;
    if (stack_lb[sp] > s.thresh) continue;
    const detail::WideNode& n = d.nodes[static_cast<std::size_t>(stack[sp])];
    float v[4];
    int order[4];
    sort4(detail::box_distance_sq(n.boxes.row, s.lanes), v, order);
    for (int k = 3; k >= 0; --k) {
      const int i = order[k];
      const std::int32_t slot = n.child[i];
      if (v[i] > s.thresh || slot == detail::kEmptySlot) continue;
      if (detail::is_leaf(slot)) {
        s.visit_block(detail::leaf_block(slot));
      } else {
        stack[sp] = slot;
        stack_lb[sp++] = v[i];
      }
    }
  }
}

// Best-first search over nodes and leaves by box distance, so leaves are measured in order of
// their boxes and the search stops as soon as the nearest pending box is farther than the best
// triangle.
CATHBOX_COLLISION_HOT void best_first(Nearest& s, PendingBoxes& pending) {
  const TreeData& d = s.d;
  while (!pending.empty()) {
    float lb;
    const int next = pending.nearest(lb);
    if (lb > s.thresh) break;
    const std::int32_t top = pending.take(next);
    if (detail::is_leaf(top)) {
      s.visit_block(detail::leaf_block(top));
    } else if (!pending.has_room()) {
      search_subtree(s, top);
    } else {
      push_children(d, d.nodes[static_cast<std::size_t>(top)], s.lanes, pending,
                    [&](float v) { return v <= s.thresh; });
    }
  }
  s.resolve();
}

void search_tree(Nearest& s) {
  PendingBoxes pending;
  pending.push(0.0f, 0);
  best_first(s, pending);
}

// Calls fn(block) for every leaf whose box lies within sqrt(thresh) of p, below the `sp` slots
// already on the stack (nodes or leaves).
template <typename Fn>
void for_each_leaf_below(const TreeData& d, const PointLanes& p, float thresh, std::int32_t (&stack)[kStackSize],
                         int sp, Fn&& fn) {
  while (sp > 0) {
    const std::int32_t top = stack[--sp];
    if (detail::is_leaf(top)) {
      fn(d.blocks[static_cast<std::size_t>(detail::leaf_block(top))]);
      continue;
    }
    const detail::WideNode& n = d.nodes[static_cast<std::size_t>(top)];
    float v[4];
    const v4f lb = detail::box_distance_sq(n.boxes.row, p);
    std::memcpy(v, &lb, sizeof v);
    for (int i = 0; i < 4; ++i) {
      const std::int32_t slot = n.child[i];
      if (v[i] > thresh || slot == detail::kEmptySlot) continue;
      if (detail::is_leaf(slot)) {
        fn(d.blocks[static_cast<std::size_t>(detail::leaf_block(slot))]);
      } else {
        stack[sp++] = slot;
      }
    }
  }
}

template <typename Fn>
void for_each_leaf_near(const TreeData& d, const PointLanes& p, float thresh, Fn&& fn) {
  std::int32_t stack[kStackSize];
  stack[0] = 0;
  for_each_leaf_below(d, p, thresh, stack, 1, fn);
}

}  // namespace

}  // namespace cathbox::collision
