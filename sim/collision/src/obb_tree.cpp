#include "collision/obb_tree.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <new>
#include <span>

#include <glm/geometric.hpp>

#include "base/xxh_hasher.hpp"
#include "float_bounds.hpp"
#include "kernels.hpp"
#include "tree_data.hpp"
#include "triangle_geometry.hpp"

namespace cathbox::collision {

using detail::PointLanes;
using detail::TreeData;
using detail::v4f;

namespace {

constexpr int kStackSize = 256 + QueryHint::kSlots;  // > hint slots + 3 * max wide depth + 4
constexpr int kMaxCandidates = 128;   // triangles touching one sphere or capsule
constexpr float kInfF = std::numeric_limits<float>::infinity();
constexpr double kInf = std::numeric_limits<double>::infinity();

bool finite(const glm::dvec3& p) { return std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z); }

float slack_for(const TreeData& d, const glm::dvec3& p) { return detail::slack_for(d.scale_mm, p); }
using detail::threshold_sq;

PointLanes lanes_of(const glm::dvec3& p) {
  return detail::splat_point(static_cast<float>(p.x), static_cast<float>(p.y), static_cast<float>(p.z));
}

// Starts loading a node or block that is about to be tested (their misses dominate).
template <typename T>
CATHBOX_COLLISION_INLINE void prefetch(const T& object) {
  const char* p = reinterpret_cast<const char*>(&object);
  for (std::size_t line = 0; line < sizeof(T); line += 64) __builtin_prefetch(p + line);
}

// Lane order by ascending value.
CATHBOX_COLLISION_INLINE void sort4(v4f values, float (&v)[4], int (&order)[4]) {
  std::memcpy(v, &values, sizeof v);
  for (int i = 0; i < 4; ++i) order[i] = i;
  for (int i = 1; i < 4; ++i) {
    const int o = order[i];
    int j = i;
    for (; j > 0 && v[order[j - 1]] > v[o]; --j) order[j] = order[j - 1];
    order[j] = o;
  }
}

// Outward pseudo-normal of a feature of a mesh triangle: the face normal, the normalised
// sum of the two face normals at an edge, the angle-weighted vertex normal.
glm::dvec3 pseudo_normal(const TreeData& d, std::int32_t face, detail::TriangleFeature feature) {
  const auto f = static_cast<std::size_t>(face);
  switch (feature.kind) {
    case FeatureKind::kFace:
      return d.face_normals[f];
    case FeatureKind::kEdge: {
      const std::int32_t opp = d.opposite[3 * f + feature.index];
      glm::dvec3 n = d.face_normals[f];
      if (opp >= 0) n += d.face_normals[static_cast<std::size_t>(opp)];
      const double len = glm::length(n);
      return len > 0.0 ? n / len : d.face_normals[f];
    }
    case FeatureKind::kVertex:
      return d.vertex_normals[d.triangles[3 * f + feature.index]];
  }
  return d.face_normals[f];
}

// The answer of a closest-point search whose nearest triangle is `face` (q on it, at squared
// distance dsq from p); block_normal: the unit normal its leaf block stores (0 for slivers).
ClosestPoint closest_from(const TreeData& d, const glm::dvec3& p, const detail::PointOnTriangle& q, double dsq,
                          std::int32_t face, const glm::dvec3& block_normal, vessel::FaceRegion region) {
  ClosestPoint out;
  out.point_mm = q.point;
  out.distance_mm = std::sqrt(dsq);
  const double n_len = glm::length(block_normal);
  out.normal = q.feature.kind == FeatureKind::kFace && n_len > 0.5 ? block_normal / n_len
                                                                   : pseudo_normal(d, face, q.feature);
  out.signed_distance_mm = glm::dot(p - q.point, out.normal) < 0.0 ? -out.distance_mm : out.distance_mm;
  out.face = face;
  out.region = region;
  out.feature = q.feature.kind;
  out.feature_index = q.feature.index;
  return out;
}

glm::dvec3 block_normal(const detail::TriangleBlock& b, int lane) {
  return glm::dvec3{b.row[detail::kRowN][lane], b.row[detail::kRowN + 1][lane], b.row[detail::kRowN + 2][lane]};
}

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

// ---- the per-node cut of the tree (QueryHint) ----------------------------------------------

}  // namespace

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

namespace {

// ---- contacts ------------------------------------------------------------------------------

// Plain data without initialisers, so the collector's fixed array costs nothing to set up.
struct Candidate {
  double distance_sq;
  glm::dvec3 wall;
  glm::dvec3 tool;  // the point of the sphere centre or capsule axis
  double segment_t;
  std::int32_t face;
  detail::TriangleFeature feature;
  std::uint64_t key;
  vessel::FaceRegion region;
};

std::uint64_t feature_key(const TreeData& d, const Candidate& c) {
  const std::uint32_t* v = &d.triangles[3 * static_cast<std::size_t>(c.face)];
  switch (c.feature.kind) {
    case FeatureKind::kFace:
      return static_cast<std::uint64_t>(c.face);
    case FeatureKind::kEdge: {
      const std::uint64_t u = v[c.feature.index];
      const std::uint64_t w = v[(c.feature.index + 1u) % 3u];
      return (1ull << 62) | (std::min(u, w) << 31) | std::max(u, w);
    }
    case FeatureKind::kVertex:
      return (2ull << 62) | v[c.feature.index];
  }
  return 0;
}

// Triangles that report the same edge or vertex: it is a local minimum of the distance only
// if every triangle around it does.
std::uint32_t expected_reports(const TreeData& d, const Candidate& c) {
  switch (c.feature.kind) {
    case FeatureKind::kFace:
      return 1;
    case FeatureKind::kEdge:
      return d.opposite[3 * static_cast<std::size_t>(c.face) + c.feature.index] >= 0 ? 2u : 1u;
    case FeatureKind::kVertex:
      return d.valence[d.triangles[3 * static_cast<std::size_t>(c.face) + c.feature.index]];
  }
  return 1;
}

class ContactCollector {
 public:
  ContactCollector(const TreeData& data, double radius) : d_(data), radius_sq_(radius * radius), radius_(radius) {}

  // c was measured on lane `lane` of block b.
  void add(const Candidate& c, const detail::TriangleBlock& b, int lane) {
    if (!(c.distance_sq < radius_sq_)) return;
    if (!has_deepest_ || c.distance_sq < deepest_.distance_sq ||
        (c.distance_sq == deepest_.distance_sq && c.face < deepest_.face)) {
      deepest_ = c;
      deepest_normal_ = block_normal(b, lane);
      has_deepest_ = true;
    }
    if (n_ < kMaxCandidates) {
      items_[n_++] = c;
    } else {
      overflow_ = true;
    }
  }

  // The nearest wall point to the sphere centre (the nearest candidate: every triangle closer
  // than the radius was offered), if any lies within the radius.
  [[nodiscard]] std::optional<ClosestPoint> nearest() const {
    if (!has_deepest_) return std::nullopt;
    return closest_from(d_, deepest_.tool, {deepest_.wall, deepest_.feature}, deepest_.distance_sq, deepest_.face,
                        deepest_normal_, deepest_.region);
  }

  std::size_t finish(std::span<Contact> out) {
    if (!has_deepest_ || out.empty()) return 0;
    // Indices of the kept candidates (kMaxCandidates marks the deepest, kept separately).
    int kept[kMaxCandidates + 1];
    double depth[kMaxCandidates + 1];
    int nk = 0;
    if (!overflow_) {
      for (int i = 0; i < n_; ++i) items_[i].key = feature_key(d_, items_[i]);
      // By feature, then face: the triangles sharing an edge or a vertex report it with
      // points a few ulps apart, and the one kept must not depend on the order the tree
      // offered them (float bounds: the x86 builds' reciprocal estimate and fused clones, a
      // division in WebAssembly). Kept first-offered, the native and the WebAssembly sessions
      // took a crease's second plane from different faces and split (issue 29's line search).
      std::sort(items_, items_ + n_, [](const Candidate& a, const Candidate& b) {
        return a.key != b.key ? a.key < b.key : a.face < b.face;
      });
      bool deepest_kept = false;
      const std::uint64_t deepest_key = feature_key(d_, deepest_);
      for (int i = 0; i < n_;) {
        int j = i + 1;
        while (j < n_ && items_[j].key == items_[i].key) ++j;
        if (static_cast<std::uint32_t>(j - i) == expected_reports(d_, items_[i])) {
          kept[nk++] = i;
          if (items_[i].key == deepest_key) deepest_kept = true;
        }
        i = j;
      }
      if (!deepest_kept) kept[nk++] = kMaxCandidates;
    } else {
      kept[nk++] = kMaxCandidates;
    }
    for (int k = 0; k < nk; ++k) depth[k] = make_contact(candidate(kept[k])).depth_mm;
    int order[kMaxCandidates + 1];
    for (int k = 0; k < nk; ++k) order[k] = k;
    // Equal depths keep the candidates' order (a total order: std::sort's handling of equal
    // elements is the library's).
    std::sort(order, order + nk, [&](int a, int b) { return depth[a] != depth[b] ? depth[a] > depth[b] : a < b; });
    const std::size_t n = std::min(static_cast<std::size_t>(nk), out.size());
    for (std::size_t k = 0; k < n; ++k) out[k] = make_contact(candidate(kept[order[k]]));
    return n;
  }

 private:
  const Candidate& candidate(int index) const { return index == kMaxCandidates ? deepest_ : items_[index]; }

  Contact make_contact(const Candidate& c) const {
    Contact out;
    out.wall_point_mm = c.wall;
    out.face = c.face;
    out.region = c.region;
    out.segment_t = c.segment_t;
    const glm::dvec3 n = pseudo_normal(d_, c.face, c.feature);
    const glm::dvec3 v = c.tool - c.wall;
    const double dist = std::sqrt(c.distance_sq);
    if (dist > 1e-12 * (d_.scale_mm + 1.0)) {
      const glm::dvec3 dir = v / dist;
      if (glm::dot(v, n) <= 0.0) {
        out.normal = dir;
        out.depth_mm = radius_ - dist;
      } else {
        out.normal = -dir;
        out.depth_mm = radius_ + dist;
      }
    } else {
      out.normal = -n;
      out.depth_mm = radius_;
    }
    return out;
  }

  const TreeData& d_;
  double radius_sq_;
  double radius_;
  Candidate items_[kMaxCandidates];
  int n_ = 0;
  bool overflow_ = false;
  Candidate deepest_;
  glm::dvec3 deepest_normal_{0.0};  // its leaf block's unit normal (closest_from)
  bool has_deepest_ = false;
};

// Probes take a leaf block.
struct SphereProbe {
  glm::dvec3 centre;
  PointLanes lanes;
  float thresh;
  ContactCollector& out;
  void operator()(const detail::TriangleBlock& b) const {
    float v[4];
    const v4f lb = detail::triangle_distance_sq(b, lanes).lower;
    std::memcpy(v, &lb, sizeof v);
    for (int i = 0; i < 4; ++i) {
      const std::int32_t f = b.face[i];
      if (f < 0 || v[i] > thresh) continue;
      glm::dvec3 ta, tb, tc;
      detail::block_corners(b, i, ta, tb, tc);
      const detail::PointOnTriangle q = detail::closest_on_triangle(centre, ta, tb, tc);
      const glm::dvec3 diff = centre - q.point;
      out.add({glm::dot(diff, diff), q.point, centre, 0.0, f, q.feature, 0, b.region}, b, i);
    }
  }
};

struct CapsuleProbe {
  glm::dvec3 a;
  glm::dvec3 b;
  ContactCollector& out;
  void operator()(const detail::TriangleBlock& blk) const {
    for (int i = 0; i < 4; ++i) {
      const std::int32_t f = blk.face[i];
      if (f < 0) continue;
      glm::dvec3 ta, tb, tc;
      detail::block_corners(blk, i, ta, tb, tc);
      const detail::SegmentOnTriangle q = detail::closest_segment_triangle(a, b, ta, tb, tc);
      out.add({q.distance_sq, q.on_triangle.point, a + q.segment_t * (b - a), q.segment_t, f,
               q.on_triangle.feature, 0, blk.region}, blk, i);
    }
  }
};

bool valid_radius(double r) { return std::isfinite(r) && r >= 0.0; }

// Runs a probe over every block that may hold a triangle within `reach` of `centre`, below the
// hint's cut when it covers that ball, else after refilling it.
template <typename Probe>
void probe_near(const TreeData& d, QueryHint& hint, const glm::dvec3& centre, double reach, float thresh,
                const Probe& probe) {
  const bool usable = HintCache::usable(hint, d);
  double delta = usable ? HintCache::moved(hint, centre) : 0.0;
  if (usable && reach + delta <= hint.radius_mm()) {
    HintCache::count_hit(hint);
    if (HintCache::clear_of(hint, delta, reach)) return;  // nothing in reach
  } else {
    HintCache::refill(d, centre, reach + 2.0 * d.coherence_margin_mm, hint);
    delta = 0.0;
  }
  HintCache::for_each_leaf_near(hint, d, centre, delta, thresh, probe);
}

}  // namespace

// ---- public queries --------------------------------------------------------------------------

const TreeStats& ObbTree::stats() const { return data_->stats; }

std::uint64_t ObbTree::content_hash() const {
  const detail::TreeData& d = *data_;
  base::XxhHasher h;  // in memory only: equal trees, equal hashes within one build
  h.add_span(std::span(d.nodes));
  for (const detail::TriangleBlock& b : d.blocks) {  // field by field: the block has padding
    h.add_span(std::span<const float>(&b.row[0][0], detail::kTriangleRows * 4));
    h.add_span(std::span<const std::int32_t>(b.face));
    const std::int32_t region[2] = {static_cast<std::int32_t>(b.region.kind), b.region.id};
    h.add_span(std::span<const std::int32_t>(region));
  }
  h.add_span(std::span(d.positions));
  h.add_span(std::span(d.triangles));
  for (const vessel::FaceRegion& r : d.regions) {
    const std::int32_t region[2] = {static_cast<std::int32_t>(r.kind), r.id};
    h.add_span(std::span<const std::int32_t>(region));
  }
  h.add_span(std::span(d.face_normals));
  h.add_span(std::span(d.vertex_normals));
  h.add_span(std::span(d.opposite));
  h.add_span(std::span(d.valence));
  const double scalars[2] = {d.scale_mm, d.coherence_margin_mm};
  h.add_span(std::span<const double>(scalars));
  return h.digest();
}

namespace {

std::optional<ClosestPoint> finish_closest(const Nearest& s) {
  if (s.face < 0) return std::nullopt;
  // Only values are kept from the search: a refill may have rewritten the hint's blocks since.
  return closest_from(s.d, s.p, s.best_point, s.best_sq, s.face, s.best_face_normal, s.best_block->region);
}

bool valid_max_distance(double m) { return !std::isnan(m) && m >= 0.0; }

}  // namespace

std::optional<ClosestPoint> ObbTree::closest_point(const glm::dvec3& point_mm, double max_distance_mm) const {
  if (!finite(point_mm) || !valid_max_distance(max_distance_mm)) return std::nullopt;
  Nearest s(*data_, point_mm, max_distance_mm);
  search_tree(s);
  return finish_closest(s);
}

std::optional<ClosestPoint> ObbTree::closest_point(const glm::dvec3& point_mm, double max_distance_mm,
                                                   QueryHint& hint) const {
  if (!finite(point_mm) || !valid_max_distance(max_distance_mm)) return std::nullopt;
  const TreeData& d = *data_;
  Nearest s(d, point_mm, max_distance_mm);
  const double margin2 = 2.0 * d.coherence_margin_mm;
  if (HintCache::usable(hint, d)) {
    const double delta = HintCache::moved(hint, point_mm);
    if (HintCache::clear_of(hint, delta, max_distance_mm)) {  // the wall is out of reach
      HintCache::count_hit(hint);
      return std::nullopt;
    }
    HintCache::search(hint, s, delta);
    if (s.bound() + delta <= hint.radius_mm()) {
      HintCache::count_hit(hint);
      HintCache::remember(hint, s, delta);
      return finish_closest(s);
    }
    // s holds a real triangle's distance (or the limit): a cut around the point that covers it
    // and the margin holds the answer.
    if (std::isfinite(s.bound())) {
      HintCache::refill(d, point_mm, s.bound() + margin2, hint);
      HintCache::search(hint, s, 0.0);
      HintCache::remember(hint, s, 0.0);
      return finish_closest(s);
    }
  }
  // No usable hint (or nothing at all within an unlimited reach of its cut): the tree, then a
  // cut around the answer. An unlimited search of a tree always finds a triangle.
  search_tree(s);
  if (std::isfinite(s.bound())) {
    HintCache::refill(d, point_mm, s.bound() + margin2, hint);
    HintCache::remember(hint, s, 0.0);
  }
  return finish_closest(s);
}

std::optional<double> ObbTree::signed_distance(const glm::dvec3& point_mm) const {
  const auto c = closest_point(point_mm);
  if (!c) return std::nullopt;
  return c->signed_distance_mm;
}

std::optional<bool> ObbTree::contains(const glm::dvec3& point_mm) const {
  const auto s = signed_distance(point_mm);
  if (!s) return std::nullopt;
  return *s < 0.0;
}

std::size_t ObbTree::sphere_contacts(const glm::dvec3& centre_mm, double radius_mm, std::span<Contact> out) const {
  if (!finite(centre_mm) || !valid_radius(radius_mm)) return 0;
  const TreeData& d = *data_;
  ContactCollector collector(d, radius_mm);
  const PointLanes lanes = lanes_of(centre_mm);
  const float thresh = threshold_sq(radius_mm, slack_for(d, centre_mm));
  for_each_leaf_near(d, lanes, thresh, SphereProbe{centre_mm, lanes, thresh, collector});
  return collector.finish(out);
}

namespace {

// The hinted sphere query; with `nearest`, also the nearest of its candidates (the closest
// point when one lies within the radius).
std::size_t hinted_sphere_contacts(const TreeData& d, const glm::dvec3& centre_mm, double radius_mm, std::span<Contact> out,
                                   QueryHint& hint, std::optional<ClosestPoint>* nearest) {
  ContactCollector collector(d, radius_mm);
  const PointLanes lanes = lanes_of(centre_mm);
  const float thresh = threshold_sq(radius_mm, slack_for(d, centre_mm));
  probe_near(d, hint, centre_mm, radius_mm, thresh, SphereProbe{centre_mm, lanes, thresh, collector});
  if (nearest != nullptr) *nearest = collector.nearest();
  return collector.finish(out);
}

}  // namespace

std::size_t ObbTree::sphere_contacts(const glm::dvec3& centre_mm, double radius_mm, std::span<Contact> out,
                                     QueryHint& hint) const {
  if (!finite(centre_mm) || !valid_radius(radius_mm)) return 0;
  return hinted_sphere_contacts(*data_, centre_mm, radius_mm, out, hint, nullptr);
}

std::size_t ObbTree::sphere_contacts(const glm::dvec3& centre_mm, double radius_mm, std::span<Contact> out,
                                     QueryHint& hint, std::optional<ClosestPoint>& nearest) const {
  nearest.reset();
  if (!finite(centre_mm) || !valid_radius(radius_mm) || out.empty()) return 0;
  return hinted_sphere_contacts(*data_, centre_mm, radius_mm, out, hint, &nearest);
}

namespace {

struct CapsuleFrame {
  glm::dvec3 mid;
  double reach;  // radius + half length
};

CapsuleFrame capsule_frame(const glm::dvec3& a, const glm::dvec3& b, double r) {
  return {(a + b) * 0.5, r + 0.5 * glm::length(b - a)};
}

}  // namespace

std::size_t ObbTree::capsule_contacts(const glm::dvec3& a_mm, const glm::dvec3& b_mm, double radius_mm,
                                      std::span<Contact> out) const {
  if (!finite(a_mm) || !finite(b_mm) || !valid_radius(radius_mm)) return 0;
  const TreeData& d = *data_;
  ContactCollector collector(d, radius_mm);
  const CapsuleFrame f = capsule_frame(a_mm, b_mm, radius_mm);
  if (!std::isfinite(f.reach)) return 0;
  for_each_leaf_near(d, lanes_of(f.mid), threshold_sq(f.reach, slack_for(d, f.mid)),
                     CapsuleProbe{a_mm, b_mm, collector});
  return collector.finish(out);
}

std::size_t ObbTree::capsule_contacts(const glm::dvec3& a_mm, const glm::dvec3& b_mm, double radius_mm,
                                      std::span<Contact> out, QueryHint& hint) const {
  if (!finite(a_mm) || !finite(b_mm) || !valid_radius(radius_mm)) return 0;
  const TreeData& d = *data_;
  ContactCollector collector(d, radius_mm);
  const CapsuleFrame f = capsule_frame(a_mm, b_mm, radius_mm);
  if (!std::isfinite(f.reach)) return 0;
  const float thresh = threshold_sq(f.reach, slack_for(d, f.mid));
  probe_near(d, hint, f.mid, f.reach, thresh, CapsuleProbe{a_mm, b_mm, collector});
  return collector.finish(out);
}

std::optional<RayHit> ObbTree::ray_cast(const glm::dvec3& origin_mm, const glm::dvec3& direction,
                                        double max_t) const {
  if (!finite(origin_mm) || !finite(direction) || std::isnan(max_t) || max_t < 0.0) return std::nullopt;
  const double dir_len = glm::length(direction);
  if (!(dir_len > 0.0)) return std::nullopt;
  const TreeData& d = *data_;
  const PointLanes o = lanes_of(origin_mm);
  const PointLanes dl = lanes_of(direction);
  const float grow = slack_for(d, origin_mm);
  const double t_slack = static_cast<double>(grow) / dir_len;
  double best_t = max_t;
  std::int32_t best_face = -1;
  vessel::FaceRegion best_region{};
  auto limit = [&]() {
    const double l = best_t * (1.0 + 1e-5) + t_slack;
    return l < 1e30 ? static_cast<float>(l) : kInfF;
  };
  std::int32_t stack[kStackSize];
  float stack_t[kStackSize];
  int sp = 0;
  stack[sp] = 0;
  stack_t[sp++] = 0.0f;
  while (sp > 0) {
    --sp;
    if (stack_t[sp] > limit()) continue;
    const detail::WideNode& n = d.nodes[static_cast<std::size_t>(stack[sp])];
    float v[4];
    int order[4];
    sort4(detail::box_ray_entry(n.boxes.row, o, dl, limit(), grow), v, order);
    std::int32_t push[4];
    float push_t[4];
    int np = 0;
    for (int i : order) {
      const std::int32_t slot = n.child[i];
      if (slot == detail::kEmptySlot || !(v[i] <= limit())) continue;
      if (!detail::is_leaf(slot)) {
        push[np] = slot;
        push_t[np++] = v[i];
        continue;
      }
      const detail::TriangleBlock& b = d.blocks[static_cast<std::size_t>(detail::leaf_block(slot))];
      for (int k = 0; k < 4; ++k) {
        const std::int32_t f = b.face[k];
        if (f < 0) continue;
        glm::dvec3 ta, tb, tc;
        detail::block_corners(b, k, ta, tb, tc);
        const auto t = detail::ray_triangle(origin_mm, direction, ta, tb, tc, best_t);
        if (t && (*t < best_t || best_face < 0)) {
          best_t = *t;
          best_face = f;
          best_region = b.region;
        }
      }
    }
    for (int k = np - 1; k >= 0; --k) {
      stack[sp] = push[k];
      stack_t[sp++] = push_t[k];
    }
  }
  if (best_face < 0) return std::nullopt;
  RayHit hit;
  hit.t = best_t;
  hit.point_mm = origin_mm + best_t * direction;
  hit.face = best_face;
  hit.normal = d.face_normals[static_cast<std::size_t>(best_face)];
  hit.front_face = glm::dot(direction, hit.normal) < 0.0;
  hit.region = best_region;
  return hit;
}

}  // namespace cathbox::collision
