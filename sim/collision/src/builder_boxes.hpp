#pragma once
// TreeBuilder's box fitting: moments of points (shifted sums), the dominant axis of their
// covariance (the split direction), a box in a given frame or along the principal axes around
// points.
// Part of tree_builder.cpp's translation unit (see builder_faces.hpp), included before Builder's
// class.
namespace cathbox::collision {

namespace detail {

// Mean and covariance (xx, yy, zz, xy, xz, yz) of points, in one pass.
struct Moments {
  glm::dvec3 mean{0.0};
  double cov[6] = {0, 0, 0, 0, 0, 0};
};

}  // namespace detail

namespace {

using detail::Moments;

// Sums of points relative to the first one (shifted sums keep the precision), in Real.
template <typename Real>
struct MomentSums {
  using Vec = glm::vec<3, Real>;
  Vec origin{Real(0)};
  Vec sum{Real(0)};
  Real sq[6] = {0, 0, 0, 0, 0, 0};
  double n = 0.0;

  void add(const Vec& p) {
    if (n == 0.0) origin = p;
    const Vec q = p - origin;
    sum += q;
    sq[0] += q.x * q.x;
    sq[1] += q.y * q.y;
    sq[2] += q.z * q.z;
    sq[3] += q.x * q.y;
    sq[4] += q.x * q.z;
    sq[5] += q.y * q.z;
    n += 1.0;
  }
  [[nodiscard]] Moments moments() const {
    const glm::dvec3 mq = glm::dvec3(sum) / n;
    Moments m;
    m.mean = glm::dvec3(origin) + mq;
    const double pairs[6][2] = {{mq.x, mq.x}, {mq.y, mq.y}, {mq.z, mq.z}, {mq.x, mq.y}, {mq.x, mq.z}, {mq.y, mq.z}};
    for (int k = 0; k < 6; ++k) m.cov[k] = static_cast<double>(sq[k]) / n - pairs[k][0] * pairs[k][1];
    return m;
  }
};

template <typename Points>
Moments moments_of(Points&& points) {
  MomentSums<double> sums;
  points([&](const glm::dvec3& p) { sums.add(p); });
  return sums.moments();
}

// Dominant eigenvector of a covariance by a few power iterations (the split direction).
glm::dvec3 dominant_axis(const double cov[6]) {
  glm::dvec3 v{1.0, 0.0, 0.0};
  if (cov[1] > cov[0] && cov[1] >= cov[2]) v = {0.0, 1.0, 0.0};
  if (cov[2] > cov[0] && cov[2] > cov[1]) v = {0.0, 0.0, 1.0};
  auto apply = [&](const glm::dvec3& x) {
    return glm::dvec3{cov[0] * x.x + cov[3] * x.y + cov[4] * x.z, cov[3] * x.x + cov[1] * x.y + cov[5] * x.z,
                      cov[4] * x.x + cov[5] * x.y + cov[2] * x.z};
  };
  for (int round = 0; round < 3; ++round) {  // three products per normalisation
    const glm::dvec3 w = apply(apply(apply(v)));
    const double len = glm::length(w);
    if (!(len > 0.0) || !std::isfinite(len)) break;
    v = w / len;
  }
  return v;
}

// Box in the orthonormal frame (x, y, z) around all `points` (origin: any point near them); the
// margin covers storing it in floats.
template <typename Points>
Obb box_in_frame(const glm::dvec3& x, const glm::dvec3& y, const glm::dvec3& z, const glm::dvec3& origin,
                 Points&& points, double scale_mm) {
  Obb box;
  box.axis[0] = x;
  box.axis[1] = y;
  box.axis[2] = z;
  glm::dvec3 lo{std::numeric_limits<double>::infinity()};
  glm::dvec3 hi{-std::numeric_limits<double>::infinity()};
  points([&](const glm::dvec3& p) {
    const glm::dvec3 d = p - origin;
    const glm::dvec3 l{glm::dot(d, x), glm::dot(d, y), glm::dot(d, z)};
    lo = glm::min(lo, l);
    hi = glm::max(hi, l);
  });
  const glm::dvec3 mid = (lo + hi) * 0.5;
  box.center = origin + mid.x * x + mid.y * y + mid.z * z;
  const glm::dvec3 half = (hi - lo) * 0.5;
  const double margin = 16.0 * std::numeric_limits<float>::epsilon() * (scale_mm + half.x + half.y + half.z);
  box.half = half + glm::dvec3{margin};
  return box;
}

// Box with the principal axes of `m` around all `points`.
template <typename Points>
Obb box_around(const Moments& m, Points&& points, double scale_mm) {
  glm::dvec3 axes[3];
  detail::principal_axes(m.cov, axes);
  return box_in_frame(axes[0], axes[1], axes[2], m.mean, points, scale_mm);
}

}  // namespace

}  // namespace cathbox::collision
