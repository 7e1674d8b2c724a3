#include "tool/banded_cholesky.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cathbox::tool {
namespace {

// Blocks are column-major: entry (row r, column c) is v[3 c + r].
constexpr int at(int r, int c) { return 3 * c + r; }

// The symmetric s (its lower triangle) as s = U D U^T, U unit lower triangular, D diagonal, kept
// as M = U^-1 below the diagonal and R = D^-1 on it (s^-1 = M^T R M): no square roots, one
// reciprocal per pivot. A pivot d that is not positive is clamped to 1e-12 and reported.
[[gnu::always_inline]] inline void factor_ldlt(const double* s, double* f, bool& ok) {
  const auto pivot = [&ok](double v) {
    if (!(v > 1e-300)) {
      ok = false;
      v = 1e-12;
    }
    return v;
  };
  const double r0 = 1.0 / pivot(s[at(0, 0)]);
  const double l10 = s[at(1, 0)] * r0;
  const double l20 = s[at(2, 0)] * r0;
  const double r1 = 1.0 / pivot(s[at(1, 1)] - l10 * s[at(1, 0)]);
  const double e21 = s[at(2, 1)] - l20 * s[at(1, 0)];
  const double l21 = e21 * r1;
  f[at(0, 0)] = r0;
  f[at(1, 1)] = r1;
  f[at(2, 2)] = 1.0 / pivot(s[at(2, 2)] - l20 * s[at(2, 0)] - l21 * e21);
  f[at(1, 0)] = -l10;
  f[at(2, 1)] = -l21;
  f[at(2, 0)] = l10 * l21 - l20;
  f[at(0, 1)] = 0.0;
  f[at(0, 2)] = 0.0;
  f[at(1, 2)] = 0.0;
}

// out = x M^T, M the unit lower triangle below f's diagonal.
[[gnu::always_inline]] inline void times_unit_upper(const double* x, const double* f, double* out) {
#pragma GCC unroll 3
  for (int r = 0; r < 3; ++r) {
    out[at(r, 0)] = x[at(r, 0)];
    out[at(r, 1)] = x[at(r, 1)] + x[at(r, 0)] * f[at(1, 0)];
    out[at(r, 2)] = x[at(r, 2)] + x[at(r, 0)] * f[at(2, 0)] + x[at(r, 1)] * f[at(2, 1)];
  }
}

// out = x R, R the diagonal of f.
[[gnu::always_inline]] inline void times_diagonal(const double* x, const double* f, double* out) {
#pragma GCC unroll 3
  for (int c = 0; c < 3; ++c) {
#pragma GCC unroll 3
    for (int r = 0; r < 3; ++r) out[at(r, c)] = x[at(r, c)] * f[at(c, c)];
  }
}

// x -= y z^T.
[[gnu::always_inline]] inline void subtract_product_transposed(double* x, const double* y, const double* z) {
#pragma GCC unroll 3
  for (int c = 0; c < 3; ++c) {
#pragma GCC unroll 3
    for (int r = 0; r < 3; ++r) {
      x[at(r, c)] -= y[at(r, 0)] * z[at(c, 0)] + y[at(r, 1)] * z[at(c, 1)] + y[at(r, 2)] * z[at(c, 2)];
    }
  }
}

// s -= x y^T on the lower triangle of s (the upper one is not read).
[[gnu::always_inline]] inline void subtract_product_lower(double* s, const double* x, const double* y) {
#pragma GCC unroll 3
  for (int c = 0; c < 3; ++c) {
#pragma GCC unroll 3
    for (int r = c; r < 3; ++r) {
      s[at(r, c)] -= x[at(r, 0)] * y[at(c, 0)] + x[at(r, 1)] * y[at(c, 1)] + x[at(r, 2)] * y[at(c, 2)];
    }
  }
}

// v -= m u.
[[gnu::always_inline]] inline void subtract_times(double* v, const double* m, const double* u) {
#pragma GCC unroll 3
  for (int r = 0; r < 3; ++r) v[r] -= m[at(r, 0)] * u[0] + m[at(r, 1)] * u[1] + m[at(r, 2)] * u[2];
}

// v -= m^T u.
[[gnu::always_inline]] inline void subtract_transposed_times(double* v, const double* m, const double* u) {
#pragma GCC unroll 3
  for (int c = 0; c < 3; ++c) v[c] -= m[at(0, c)] * u[0] + m[at(1, c)] * u[1] + m[at(2, c)] * u[2];
}

}  // namespace

BandedCholesky::BandedCholesky(std::size_t max_nodes)
    : a_(max_nodes * (kBlockBand + 1), Block{}),
      l1_(max_nodes, Block{}),
      l2_(max_nodes, Block{}),
      dinv_(max_nodes, Block{}) {}

double BandedCholesky::get(std::size_t i, std::size_t j) const {
  if (i < j) std::swap(i, j);
  const std::size_t a = i / 3;
  const std::size_t b = j / 3;
  if (a - b > kBlockBand) return 0.0;
  return block(a, b).v[at(static_cast<int>(i % 3), static_cast<int>(j % 3))];
}

void BandedCholesky::multiply_add(const double* x, double* y, std::size_t row_first,
                                  std::size_t row_last, std::size_t col_first,
                                  std::size_t col_last) const {
  constexpr std::size_t kBand = 3 * kBlockBand + 2;  // widest reach of a row, in unknowns
  // Only rows within the band of the columns can meet them.
  row_first = std::max(row_first, col_first > kBand ? col_first - kBand : 0);
  row_last = std::min(row_last, col_last + kBand);
  for (std::size_t i = row_first; i < row_last; ++i) {
    const std::size_t lo = std::max(col_first, i > kBand ? i - kBand : 0);
    const std::size_t hi = std::min(col_last, i + kBand + 1);
    double sum = 0.0;
    for (std::size_t j = lo; j < hi; ++j) sum += get(i, j) * x[j];
    y[i] += sum;
  }
}

bool BandedCholesky::factor(std::size_t first_node) {
  first_ = first_node;
  return factor_rows(first_node);
}

bool BandedCholesky::refactor_from(std::size_t from) { return factor_rows(std::max(from, first_)); }

bool BandedCholesky::factor_rows(std::size_t from) {
  const std::size_t first_node = first_;
  bool ok = true;
  for (std::size_t i = from; i < n_; ++i) {
    // The block Cholesky factorisation with each diagonal factor L(i, i) = U_i R_i^-1/2
    // (factor_ldlt) and each off-diagonal one C = G R^1/2 kept as G:
    // G(i, i-2) = A(i, i-2) M(i-2)^T
    // G(i, i-1) = (A(i, i-1) - G(i, i-2) R(i-2) G(i-1, i-2)^T) M(i-1)^T
    // U_i R_i^-1 U_i^T = A(i, i) - G(i, i-2) R(i-2) G(i, i-2)^T - G(i, i-1) R(i-1) G(i, i-1)^T
    // Same arithmetic as L L^T but for the square roots.
    Block s = block(i, i);
    Block& c = l2_[i];
    Block& b = l1_[i];
    c = Block{};
    b = Block{};
    Block cr{};
    if (i >= first_node + 2) {
      times_unit_upper(block(i, i - 2).v, dinv_[i - 2].v, c.v);
      times_diagonal(c.v, dinv_[i - 2].v, cr.v);
      subtract_product_lower(s.v, cr.v, c.v);
    }
    if (i >= first_node + 1) {
      Block t = block(i, i - 1);
      if (i >= first_node + 2) subtract_product_transposed(t.v, cr.v, l1_[i - 1].v);
      times_unit_upper(t.v, dinv_[i - 1].v, b.v);
      Block br;
      times_diagonal(b.v, dinv_[i - 1].v, br.v);
      subtract_product_lower(s.v, br.v, b.v);
    }
    factor_ldlt(s.v, dinv_[i].v, ok);
  }
  return ok;
}

void BandedCholesky::solve(double* v) const {
  // Forward: u_i = R_i M_i (v_i - G(i, i-1) u_(i-1) - G(i, i-2) u_(i-2)).
  for (std::size_t i = first_; i < n_; ++i) {
    double r[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    if (i >= first_ + 1) subtract_times(r, l1_[i].v, v + 3 * (i - 1));
    if (i >= first_ + 2) subtract_times(r, l2_[i].v, v + 3 * (i - 2));
    const double* f = dinv_[i].v;
    v[3 * i] = f[at(0, 0)] * r[0];
    v[3 * i + 1] = f[at(1, 1)] * (f[at(1, 0)] * r[0] + r[1]);
    v[3 * i + 2] = f[at(2, 2)] * (f[at(2, 0)] * r[0] + f[at(2, 1)] * r[1] + r[2]);
  }
  // Backward: x_i = M_i^T (u_i - R_i (G(i+1, i)^T x_(i+1) + G(i+2, i)^T x_(i+2))).
  for (std::size_t i = n_; i-- > first_;) {
    double g[3] = {0.0, 0.0, 0.0};
    if (i + 1 < n_) subtract_transposed_times(g, l1_[i + 1].v, v + 3 * (i + 1));
    if (i + 2 < n_) subtract_transposed_times(g, l2_[i + 2].v, v + 3 * (i + 2));
    const double* f = dinv_[i].v;
    const double r0 = v[3 * i] + f[at(0, 0)] * g[0];
    const double r1 = v[3 * i + 1] + f[at(1, 1)] * g[1];
    const double r2 = v[3 * i + 2] + f[at(2, 2)] * g[2];
    v[3 * i] = r0 + f[at(1, 0)] * r1 + f[at(2, 0)] * r2;
    v[3 * i + 1] = r1 + f[at(2, 1)] * r2;
    v[3 * i + 2] = r2;
  }
}

}  // namespace cathbox::tool
