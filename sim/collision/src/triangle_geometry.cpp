#include "triangle_geometry.hpp"

#include <algorithm>
#include <limits>

#include <glm/geometric.hpp>

namespace cathbox::collision::detail {

PointOnTriangle closest_on_triangle(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                    const glm::dvec3& c) {
  const glm::dvec3 ab = b - a;
  const glm::dvec3 ac = c - a;
  const glm::dvec3 ap = p - a;
  const double d1 = glm::dot(ab, ap);
  const double d2 = glm::dot(ac, ap);
  if (d1 <= 0.0 && d2 <= 0.0) return {a, {FeatureKind::kVertex, 0}};

  const glm::dvec3 bp = p - b;
  const double d3 = glm::dot(ab, bp);
  const double d4 = glm::dot(ac, bp);
  if (d3 >= 0.0 && d4 <= d3) return {b, {FeatureKind::kVertex, 1}};

  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    const double v = d1 / (d1 - d3);
    return {a + v * ab, {FeatureKind::kEdge, 0}};
  }

  const glm::dvec3 cp = p - c;
  const double d5 = glm::dot(ab, cp);
  const double d6 = glm::dot(ac, cp);
  if (d6 >= 0.0 && d5 <= d6) return {c, {FeatureKind::kVertex, 2}};

  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    const double w = d2 / (d2 - d6);
    return {a + w * ac, {FeatureKind::kEdge, 2}};
  }

  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {b + w * (c - b), {FeatureKind::kEdge, 1}};
  }

  const double denom = 1.0 / (va + vb + vc);
  const double v = vb * denom;
  const double w = vc * denom;
  return {a + ab * v + ac * w, {FeatureKind::kFace, 0}};
}

double point_triangle_distance_sq(const glm::dvec3& p, const glm::dvec3& a, const glm::dvec3& b,
                                  const glm::dvec3& c) {
  const glm::dvec3 d = p - closest_on_triangle(p, a, b, c).point;
  return glm::dot(d, d);
}


namespace {

// Where segment p0-p1 crosses triangle abc, if it does.
std::optional<SegmentOnTriangle> segment_crossing(const glm::dvec3& p0, const glm::dvec3& p1,
                                                  const glm::dvec3& a, const glm::dvec3& b,
                                                  const glm::dvec3& c) {
  const glm::dvec3 n = glm::cross(b - a, c - a);
  const double s0 = glm::dot(p0 - a, n);
  const double s1 = glm::dot(p1 - a, n);
  if ((s0 > 0.0 && s1 > 0.0) || (s0 < 0.0 && s1 < 0.0) || s0 == s1) return std::nullopt;
  const double t = s0 / (s0 - s1);
  const glm::dvec3 x = p0 + t * (p1 - p0);
  // Inside test by the signs of the sub-triangle areas.
  const double wa = glm::dot(glm::cross(b - x, c - x), n);
  const double wb = glm::dot(glm::cross(c - x, a - x), n);
  const double wc = glm::dot(glm::cross(a - x, b - x), n);
  if (wa < 0.0 || wb < 0.0 || wc < 0.0) return std::nullopt;
  SegmentOnTriangle out;
  out.segment_t = t;
  out.distance_sq = 0.0;
  out.on_triangle = {x, {FeatureKind::kFace, 0}};
  return out;
}

}  // namespace

SegmentOnTriangle closest_segment_triangle(const glm::dvec3& p0, const glm::dvec3& p1,
                                           const glm::dvec3& a, const glm::dvec3& b,
                                           const glm::dvec3& c) {
  if (auto crossing = segment_crossing(p0, p1, a, b, c)) return *crossing;
  SegmentOnTriangle best;
  best.distance_sq = std::numeric_limits<double>::infinity();
  const glm::dvec3 ends[2] = {p0, p1};
  for (int i = 0; i < 2; ++i) {
    const PointOnTriangle q = closest_on_triangle(ends[i], a, b, c);
    const glm::dvec3 d = ends[i] - q.point;
    const double dsq = glm::dot(d, d);
    if (dsq < best.distance_sq) best = {static_cast<double>(i), dsq, q};
  }
  const glm::dvec3 corners[3] = {a, b, c};
  for (std::uint8_t k = 0; k < 3; ++k) {
    const glm::dvec3& q0 = corners[k];
    const glm::dvec3& q1 = corners[(k + 1) % 3];
    const SegmentPair pair = closest_segment_segment(p0, p1, q0, q1);
    if (pair.distance_sq < best.distance_sq) {
      TriangleFeature feature{FeatureKind::kEdge, k};
      glm::dvec3 point = q0 + pair.t * (q1 - q0);
      if (pair.t <= 0.0) {
        feature = {FeatureKind::kVertex, k};
        point = q0;
      } else if (pair.t >= 1.0) {
        feature = {FeatureKind::kVertex, static_cast<std::uint8_t>((k + 1) % 3)};
        point = q1;
      }
      best = {pair.s, pair.distance_sq, {point, feature}};
    }
  }
  return best;
}

std::optional<double> ray_triangle(const glm::dvec3& origin, const glm::dvec3& dir,
                                   const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c,
                                   double max_t) {
  const glm::dvec3 e1 = b - a;
  const glm::dvec3 e2 = c - a;
  const glm::dvec3 pv = glm::cross(dir, e2);
  const double det = glm::dot(e1, pv);
  if (det == 0.0) return std::nullopt;
  const double inv = 1.0 / det;
  const glm::dvec3 tv = origin - a;
  const double u = glm::dot(tv, pv) * inv;
  if (u < 0.0 || u > 1.0) return std::nullopt;
  const glm::dvec3 qv = glm::cross(tv, e1);
  const double v = glm::dot(dir, qv) * inv;
  if (v < 0.0 || u + v > 1.0) return std::nullopt;
  const double t = glm::dot(e2, qv) * inv;
  if (t < 0.0 || t > max_t) return std::nullopt;
  return t;
}

}  // namespace cathbox::collision::detail

namespace cathbox::collision {

SegmentPair closest_segment_segment(const glm::dvec3& p0, const glm::dvec3& p1,
                                    const glm::dvec3& q0, const glm::dvec3& q1) {
  const glm::dvec3 d1 = p1 - p0;
  const glm::dvec3 d2 = q1 - q0;
  const glm::dvec3 r = p0 - q0;
  const double a = glm::dot(d1, d1);
  const double e = glm::dot(d2, d2);
  const double f = glm::dot(d2, r);
  double s = 0.0;
  double t = 0.0;
  if (a <= 0.0 && e <= 0.0) {
    // both points
  } else if (a <= 0.0) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = glm::dot(d1, r);
    if (e <= 0.0) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = glm::dot(d1, d2);
      const double denom = a * e - b * b;
      s = denom > 0.0 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0.0) {
        t = 0.0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1.0) {
        t = 1.0;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  const glm::dvec3 diff = (p0 + d1 * s) - (q0 + d2 * t);
  return {s, t, glm::dot(diff, diff)};
}

}  // namespace cathbox::collision
