#include "obb_fit.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include <glm/geometric.hpp>

namespace cathbox::collision::detail {

namespace {

// Eigenvector of A for eigenvalue lambda: the longest cross product of two rows of A - lambda I.
bool eigenvector(const double a[3][3], double lambda, glm::dvec3& out) {
  const glm::dvec3 r0{a[0][0] - lambda, a[0][1], a[0][2]};
  const glm::dvec3 r1{a[1][0], a[1][1] - lambda, a[1][2]};
  const glm::dvec3 r2{a[2][0], a[2][1], a[2][2] - lambda};
  const glm::dvec3 c[3] = {glm::cross(r0, r1), glm::cross(r0, r2), glm::cross(r1, r2)};
  int best = 0;
  double best_len = glm::dot(c[0], c[0]);
  for (int i = 1; i < 3; ++i) {
    const double len = glm::dot(c[i], c[i]);
    if (len > best_len) {
      best = i;
      best_len = len;
    }
  }
  const double scale = glm::dot(r0, r0) + glm::dot(r1, r1) + glm::dot(r2, r2);
  if (!(best_len > 1e-20 * scale * scale) || !std::isfinite(best_len)) return false;
  out = c[best] / std::sqrt(best_len);
  return true;
}

}  // namespace

void principal_axes(const double cov[6], glm::dvec3 axes[3]) {
  axes[0] = {1, 0, 0};
  axes[1] = {0, 1, 0};
  axes[2] = {0, 0, 1};
  const double a[3][3] = {{cov[0], cov[3], cov[4]}, {cov[3], cov[1], cov[5]},
                          {cov[4], cov[5], cov[2]}};
  const double off = cov[3] * cov[3] + cov[4] * cov[4] + cov[5] * cov[5];
  const double q = (cov[0] + cov[1] + cov[2]) / 3.0;
  const double p2 = (cov[0] - q) * (cov[0] - q) + (cov[1] - q) * (cov[1] - q) +
                    (cov[2] - q) * (cov[2] - q) + 2.0 * off;
  if (!(p2 > 1e-24 * (q * q + 1e-300)) || !std::isfinite(p2)) return;
  if (off <= 1e-18 * p2) {
    // Already diagonal: sort the coordinate axes by variance.
    int idx[3] = {0, 1, 2};
    std::sort(idx, idx + 3, [&](int i, int j) { return a[i][i] > a[j][j]; });
    glm::dvec3 unit[3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    axes[0] = unit[idx[0]];
    axes[1] = unit[idx[1]];
    axes[2] = glm::cross(axes[0], axes[1]);
    return;
  }
  const double p = std::sqrt(p2 / 6.0);
  double b[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) b[i][j] = (a[i][j] - (i == j ? q : 0.0)) / p;
  const double det = b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1]) -
                     b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0]) +
                     b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]);
  const double r = std::clamp(det / 2.0, -1.0, 1.0);
  const double phi = std::acos(r) / 3.0;
  const double l1 = q + 2.0 * p * std::cos(phi);
  const double l3 = q + 2.0 * p * std::cos(phi + 2.0 * std::numbers::pi / 3.0);
  glm::dvec3 v1;
  glm::dvec3 v3;
  const bool ok1 = eigenvector(a, l1, v1);
  const bool ok3 = eigenvector(a, l3, v3);
  if (!ok1 && !ok3) return;
  if (!ok1) {
    std::swap(v1, v3);
  }
  if (!ok1 || !ok3) {
    // Two equal eigenvalues: any vector orthogonal to the distinct one completes the basis.
    v3 = std::abs(v1.x) < 0.6 ? glm::dvec3{1, 0, 0} : glm::dvec3{0, 1, 0};
  }
  v3 -= glm::dot(v3, v1) * v1;
  const double len = glm::length(v3);
  if (!(len > 1e-9)) return;
  v3 /= len;
  axes[0] = v1;
  axes[2] = v3;
  axes[1] = glm::cross(v3, v1);
}

}  // namespace cathbox::collision::detail
