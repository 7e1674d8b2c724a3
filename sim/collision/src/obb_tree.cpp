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
// The queries' parts (one translation unit: see query_basics.hpp).
#include "query_basics.hpp"
#include "nearest_search.hpp"
#include "hint_cache.hpp"
#include "contact_collector.hpp"

namespace cathbox::collision {

using detail::PointLanes;
using detail::TreeData;
using detail::v4f;

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
