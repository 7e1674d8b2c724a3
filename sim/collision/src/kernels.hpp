#pragma once
// The float lane kernels: squared distance lower bounds from a point to four boxes and to four
// triangles, and ray entry distances into four boxes. They only prune; exact answers are
// computed in double afterwards.
#include <glm/vec3.hpp>

#include "simd.hpp"
#include "tree_data.hpp"

namespace cathbox::collision::detail {

struct PointLanes {
  v4f x, y, z;
};

CATHBOX_COLLISION_INLINE PointLanes splat_point(float x, float y, float z) { return {splat(x), splat(y), splat(z)}; }

CATHBOX_COLLISION_INLINE v4f row(const float (*rows)[4], int r) { return load(rows[r]); }

// Squared distance from p to each of four boxes (0 inside).
CATHBOX_COLLISION_INLINE v4f box_distance_sq(const float (*rows)[4], const PointLanes& p) {
  const v4f dx = p.x - row(rows, 0);
  const v4f dy = p.y - row(rows, 1);
  const v4f dz = p.z - row(rows, 2);
  v4f sum = splat(0.0f);
  for (int k = 0; k < 3; ++k) {
    const v4f l = dx * row(rows, 3 + 3 * k) + dy * row(rows, 4 + 3 * k) + dz * row(rows, 5 + 3 * k);
    const v4f out = vmax(vabs(l) - row(rows, 12 + k), splat(0.0f));
    sum += out * out;
  }
  return sum;
}

// Squared distance from p to each of four triangles, bracketed: `lower` takes the plane distance
// when the projection falls inside the triangle grown by a tolerance, `upper` only when it falls
// inside the triangle shrunk by it; otherwise both are the nearest of the three edges. Both are
// exact up to float rounding when the projection is clearly inside or outside.
struct DistanceBracket {
  v4f lower;
  v4f upper;
};

CATHBOX_COLLISION_INLINE DistanceBracket triangle_distance_sq(const TriangleBlock& t, const PointLanes& p) {
  const v4f wx = p.x - row(t.row, kRowA);
  const v4f wy = p.y - row(t.row, kRowA + 1);
  const v4f wz = p.z - row(t.row, kRowA + 2);
  const v4f e0x = row(t.row, kRowB) - row(t.row, kRowA);
  const v4f e0y = row(t.row, kRowB + 1) - row(t.row, kRowA + 1);
  const v4f e0z = row(t.row, kRowB + 2) - row(t.row, kRowA + 2);
  const v4f e1x = row(t.row, kRowC) - row(t.row, kRowA);
  const v4f e1y = row(t.row, kRowC + 1) - row(t.row, kRowA + 1);
  const v4f e1z = row(t.row, kRowC + 2) - row(t.row, kRowA + 2);
  const v4f plane = wx * row(t.row, kRowN) + wy * row(t.row, kRowN + 1) + wz * row(t.row, kRowN + 2);
  const v4f u = wx * row(t.row, kRowU) + wy * row(t.row, kRowU + 1) + wz * row(t.row, kRowU + 2);
  const v4f v = wx * row(t.row, kRowV) + wy * row(t.row, kRowV + 1) + wz * row(t.row, kRowV + 2);
  const v4f tol = splat(1e-3f);
  const v4i inside = (u >= -tol) & (v >= -tol) & (u + v <= splat(1.0f) + tol);
  const v4i surely_inside = (u >= tol) & (v >= tol) & (u + v <= splat(1.0f) - tol);

  // Edge parameters; an empty lane's 0 / 0 clamps to 0 (select picks the bound on NaN).
  const v4f t0 = clamp01((wx * e0x + wy * e0y + wz * e0z) * recip(e0x * e0x + e0y * e0y + e0z * e0z));
  const v4f d0x = wx - t0 * e0x, d0y = wy - t0 * e0y, d0z = wz - t0 * e0z;
  const v4f t1 = clamp01((wx * e1x + wy * e1y + wz * e1z) * recip(e1x * e1x + e1y * e1y + e1z * e1z));
  const v4f d1x = wx - t1 * e1x, d1y = wy - t1 * e1y, d1z = wz - t1 * e1z;
  const v4f e2x = e1x - e0x, e2y = e1y - e0y, e2z = e1z - e0z;
  const v4f w2x = wx - e0x, w2y = wy - e0y, w2z = wz - e0z;
  const v4f t2 = clamp01((w2x * e2x + w2y * e2y + w2z * e2z) * recip(e2x * e2x + e2y * e2y + e2z * e2z));
  const v4f d2x = w2x - t2 * e2x, d2y = w2y - t2 * e2y, d2z = w2z - t2 * e2z;
  const v4f edge = vmin(vmin(d0x * d0x + d0y * d0y + d0z * d0z, d1x * d1x + d1y * d1y + d1z * d1z),
                        d2x * d2x + d2y * d2y + d2z * d2z);
  const v4f plane_sq = plane * plane;
  return {select(inside, plane_sq, edge), select(surely_inside, plane_sq, edge)};
}

// Ray entry parameter into each of four boxes (+inf where it misses within [0, max_t]); the
// boxes are grown by `grow` to absorb float rounding.
CATHBOX_COLLISION_INLINE v4f box_ray_entry(const float (*rows)[4], const PointLanes& o, const PointLanes& d, float max_t,
                         float grow) {
  const v4f dx = o.x - row(rows, 0);
  const v4f dy = o.y - row(rows, 1);
  const v4f dz = o.z - row(rows, 2);
  v4f t_near = splat(0.0f);
  v4f t_far = splat(max_t);
  const v4f inf = splat(__builtin_inff());
  for (int k = 0; k < 3; ++k) {
    const v4f ax = row(rows, 3 + 3 * k), ay = row(rows, 4 + 3 * k), az = row(rows, 5 + 3 * k);
    const v4f lo = dx * ax + dy * ay + dz * az;
    const v4f ld = d.x * ax + d.y * ay + d.z * az;
    const v4f h = row(rows, 12 + k) + splat(grow);
    const v4f inv = splat(1.0f) / ld;
    const v4f ta = (-h - lo) * inv;
    const v4f tb = (h - lo) * inv;
    // A ray parallel to the slab is inside it for all t or for none.
    const v4i parallel = ld == splat(0.0f);
    const v4i outside = vabs(lo) > h;
    const v4f enter = select(parallel, select(outside, inf, splat(0.0f)), vmin(ta, tb));
    const v4f leave = select(parallel, select(outside, -inf, inf), vmax(ta, tb));
    t_near = vmax(t_near, enter);
    t_far = vmin(t_far, leave);
  }
  return select(t_near <= t_far, t_near, inf);
}

// The corners of lane i in double: the mesh's own float vertices, so the exact stage needs no
// other memory than the block.
CATHBOX_COLLISION_INLINE void block_corners(const TriangleBlock& t, int i, glm::dvec3& a, glm::dvec3& b,
                                            glm::dvec3& c) {
  a = {t.row[kRowA][i], t.row[kRowA + 1][i], t.row[kRowA + 2][i]};
  b = {t.row[kRowB][i], t.row[kRowB + 1][i], t.row[kRowB + 2][i]};
  c = {t.row[kRowC][i], t.row[kRowC + 1][i], t.row[kRowC + 2][i]};
}

}  // namespace cathbox::collision::detail
