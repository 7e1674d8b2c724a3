#include "tool/arterial_wall.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <numbers>

namespace cathbox::tool {

ArterialWall arterial_wall(Territory territory) {
  switch (territory) {
    case Territory::kCervical:
      return kCervicalWall;
    case Territory::kIntracranial:
      return kIntracranialWall;
  }
  return ArterialWall{};
}

WallShell::WallShell(const ArterialWall& wall, double radius_mm)
    : wall_(wall), radius_mm_(radius_mm), thickness_mm_(wall.thickness_ratio * radius_mm) {
  assert(radius_mm > 0.0 && wall.thickness_ratio > 0.0 && wall.youngs_modulus_kPa > 0.0);
  const double e = wall.youngs_modulus_kPa;  // mN/mm^2
  const double h = thickness_mm_;
  hoop_k_ = e * h / (radius_mm_ * radius_mm_);
  bending_d_ = e * h * h * h / (12.0 * (1.0 - wall.poisson * wall.poisson));
  beta_ = std::pow(hoop_k_ / (4.0 * bending_d_), 0.25);
}

double WallShell::ring_load_stiffness_mN_per_mm() const {
  return 4.0 * std::numbers::pi * radius_mm_ * hoop_k_ / beta_;
}

std::vector<double> WallShell::solve_radial(const std::vector<double>& load_kPa, double spacing_mm) const {
  // Unknowns w_1 .. w_{n-2}; w_0 = w_{n-1} = 0 and the ghosts w_{-1} = w_1, w_n = w_{n-2} (zero
  // slope). Row i: D / s^4 (w_{i-2} - 4 w_{i-1} + 6 w_i - 4 w_{i+1} + w_{i+2}) + k w_i = q_i,
  // symmetric positive definite and pentadiagonal: an LDL^T of bandwidth 2.
  const std::size_t n = load_kPa.size();
  std::vector<double> w(n, 0.0);
  if (n < 5) return w;
  const std::size_t m = n - 2;
  const double a = bending_d_ / std::pow(spacing_mm, 4);
  std::vector<double> d0(m, 6.0 * a + hoop_k_), d1(m, -4.0 * a), d2(m, a);  // diagonal, +1, +2
  d0[0] += a;      // ghost w_{-1} = w_1
  d0[m - 1] += a;  // ghost w_n = w_{n-2}
  std::vector<double> b(load_kPa.begin() + 1, load_kPa.end() - 1);
  // Banded Cholesky-free elimination (LDL^T) on the three diagonals.
  std::vector<double> dd(m), l1(m, 0.0), l2(m, 0.0);
  for (std::size_t i = 0; i < m; ++i) {
    double di = d0[i];
    if (i >= 1) di -= l1[i - 1] * l1[i - 1] * dd[i - 1];
    if (i >= 2) di -= l2[i - 2] * l2[i - 2] * dd[i - 2];
    dd[i] = di;
    if (i + 1 < m) {
      double e1 = d1[i];
      if (i >= 1) e1 -= l1[i - 1] * l2[i - 1] * dd[i - 1];
      l1[i] = e1 / di;
    }
    if (i + 2 < m) l2[i] = d2[i] / di;
  }
  for (std::size_t i = 0; i < m; ++i) {  // L y = b
    if (i >= 1) b[i] -= l1[i - 1] * b[i - 1];
    if (i >= 2) b[i] -= l2[i - 2] * b[i - 2];
  }
  for (std::size_t i = 0; i < m; ++i) b[i] /= dd[i];  // D z = y
  for (std::size_t r = m; r-- > 0;) {                 // L^T w = z
    if (r + 1 < m) b[r] -= l1[r] * b[r + 1];
    if (r + 2 < m) b[r] -= l2[r] * b[r + 2];
  }
  std::copy(b.begin(), b.end(), w.begin() + 1);
  return w;
}

}  // namespace cathbox::tool
