#pragma once
// Sphere and capsule contacts: the triangles within reach gathered (ContactCollector), one
// contact per feature of the wall (face, edge, vertex) reported once, nearest first.
// Part of obb_tree.cpp's translation unit (see query_basics.hpp).
#include <algorithm>
#include <cfloat>
#include <cstdint>
#include <iterator>

#include "hint_cache.hpp"

namespace cathbox::collision {

namespace {

// The collector's fixed array holds these in Slots, which set nothing up: the feature's and the
// region's member initialisers made every query write all 128 (~1 % of a coiling case's time).
struct Candidate {
  double distance_sq;
  glm::dvec3 wall;
  glm::dvec3 tool;  // the point of the sphere centre or capsule axis
  double segment_t;
  std::int32_t face;
  detail::TriangleFeature feature;
  vessel::FaceRegion region;
};

// Storage for one candidate that constructs nothing until a candidate is stored in it.
union Slot {
  Slot() {}  // NOLINT(modernize-use-equals-default): `= default` would initialise the candidate
  Candidate c;
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
      slots_[n_++].c = c;  // a trivial assignment: the slot's candidate begins here
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
    int nk = 0;
    if (!overflow_) {
      // By feature, then face: the triangles sharing an edge or a vertex report it with
      // points a few ulps apart, and the one kept must not depend on the order the tree
      // offered them (float bounds: the x86 builds' reciprocal estimate and fused clones, a
      // division in WebAssembly). Kept first-offered, the native and the WebAssembly sessions
      // took a crease's second plane from different faces and split (issue 29's line search).
      // Grouped by feature in a small hash table (a sort of every candidate cost as much as the
      // probe's triangle tests), each group keeping its lowest face; the groups kept are then
      // taken in feature order: what sorting all of them by (feature, face) gave.
      const int groups = group_by_feature();
      const std::uint64_t deepest_key = feature_key(d_, deepest_);
      bool deepest_kept = false;
      Group* last = groups_;
      for (int g = 0; g < groups; ++g) {
        if (groups_[g].count == expected_reports(d_, item(groups_[g].first))) *last++ = groups_[g];
      }
      std::sort(groups_, last, [](const Group& a, const Group& b) { return a.key < b.key; });
      for (const Group* g = groups_; g != last; ++g) {
        kept[nk++] = g->first;
        deepest_kept = deepest_kept || g->key == deepest_key;
      }
      if (!deepest_kept) kept[nk++] = kMaxCandidates;
    } else {
      kept[nk++] = kMaxCandidates;
    }
    double depth[kMaxCandidates + 1];
    int order[kMaxCandidates + 1];
    for (int k = 0; k < nk; ++k) depth[k] = make_contact(candidate(kept[k])).depth_mm, order[k] = k;
    // Equal depths keep the candidates' order (a total order: std::sort's handling of equal
    // elements is the library's).
    std::sort(order, order + nk, [&](int a, int b) { return depth[a] != depth[b] ? depth[a] > depth[b] : a < b; });
    const std::size_t n = std::min(static_cast<std::size_t>(nk), out.size());
    for (std::size_t k = 0; k < n; ++k) out[k] = make_contact(candidate(kept[order[k]]));
    return n;
  }

 private:
  struct Group {
    std::uint64_t key;    // feature_key
    int first;            // the candidate of the lowest face
    std::uint32_t count;  // the candidates reporting the feature
  };
  static constexpr int kTableBits = 8;  // 256 slots for at most kMaxCandidates groups
  static_assert((1 << kTableBits) >= 2 * kMaxCandidates);

  // groups_[0 .. returned): the candidates' features, each with its count and lowest face.
  int group_by_feature() {
    std::int16_t table[1 << kTableBits];
    std::fill(std::begin(table), std::end(table), std::int16_t{-1});
    int groups = 0;
    for (int i = 0; i < n_; ++i) {
      const std::uint64_t key = feature_key(d_, item(i));
      auto slot = static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> (64 - kTableBits));
      while (table[slot] >= 0 && groups_[table[slot]].key != key) slot = (slot + 1) & ((1u << kTableBits) - 1);
      if (table[slot] < 0) {
        table[slot] = static_cast<std::int16_t>(groups);
        groups_[groups++] = Group{key, i, 1};
        continue;
      }
      Group& g = groups_[table[slot]];
      ++g.count;
      if (item(i).face < item(g.first).face) g.first = i;
    }
    return groups;
  }
  const Candidate& item(int i) const { return slots_[i].c; }
  const Candidate& candidate(int index) const { return index == kMaxCandidates ? deepest_ : item(index); }

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
  Slot slots_[kMaxCandidates];
  Group groups_[kMaxCandidates];
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
      out.add({glm::dot(diff, diff), q.point, centre, 0.0, f, q.feature, b.region}, b, i);
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
               q.on_triangle.feature, blk.region}, blk, i);
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

}  // namespace cathbox::collision
