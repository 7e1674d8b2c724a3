#include "tool/banded_cholesky.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cathbox::tool {
namespace {

// Blocks are column-major: entry (row r, column c) is v[3 c + r].
constexpr int at(int r, int c) { return 3 * c + r; }

// Inverse of the symmetric s (its lower triangle) through its lower-triangular Cholesky factor
// L: L^-T L^-1. A pivot that is not positive is clamped to 1e-12 and reported. The fallback of
// inverse_symmetric for blocks that are not positive definite.
[[gnu::noinline]] void inverse_clamped(const double* s, double* inv, bool& ok) {
  const auto pivot = [&ok](double v) {
    if (!(v > 1e-300)) {
      ok = false;
      v = 1e-12;
    }
    return std::sqrt(v);
  };
  const double l00 = pivot(s[at(0, 0)]);
  const double l10 = s[at(1, 0)] / l00;
  const double l20 = s[at(2, 0)] / l00;
  const double l11 = pivot(s[at(1, 1)] - l10 * l10);
  const double l21 = (s[at(2, 1)] - l20 * l10) / l11;
  const double l22 = pivot(s[at(2, 2)] - l20 * l20 - l21 * l21);
  // The inverse of a lower-triangular matrix is lower triangular.
  const double i00 = 1.0 / l00;
  const double i11 = 1.0 / l11;
  const double i22 = 1.0 / l22;
  const double i10 = -l10 * i00 * i11;
  const double i21 = -l21 * i11 * i22;
  const double i20 = -(l20 * i00 + l21 * i10) * i22;
  // (L^-T L^-1)(r, c) = sum over k >= max(r, c) of i_kr i_kc.
  inv[at(0, 0)] = i00 * i00 + i10 * i10 + i20 * i20;
  inv[at(1, 0)] = inv[at(0, 1)] = i10 * i11 + i20 * i21;
  inv[at(2, 0)] = inv[at(0, 2)] = i20 * i22;
  inv[at(1, 1)] = i11 * i11 + i21 * i21;
  inv[at(2, 1)] = inv[at(1, 2)] = i21 * i22;
  inv[at(2, 2)] = i22 * i22;
}

// Inverse of the symmetric s (its lower triangle) by cofactors: one division on a short
// dependency chain, which the next block row waits on. A block whose leading minors are not
// positive (a Cholesky pivot <= 1e-300) goes to inverse_clamped.
[[gnu::always_inline]] inline void inverse_symmetric(const double* s, double* inv, bool& ok) {
  const double s00 = s[at(0, 0)], s10 = s[at(1, 0)], s20 = s[at(2, 0)];
  const double s11 = s[at(1, 1)], s21 = s[at(2, 1)], s22 = s[at(2, 2)];
  const double c00 = s11 * s22 - s21 * s21;
  const double c10 = s20 * s21 - s10 * s22;
  const double c20 = s10 * s21 - s11 * s20;
  const double c11 = s00 * s22 - s20 * s20;
  const double c21 = s10 * s20 - s00 * s21;
  const double c22 = s00 * s11 - s10 * s10;
  const double det = s00 * c00 + s10 * c10 + s20 * c20;
  if (!(s00 > 1e-300) || !(c22 > 1e-300 * s00) || !(det > 1e-300 * c22)) [[unlikely]] {
    inverse_clamped(s, inv, ok);
    return;
  }
  const double r = 1.0 / det;
  inv[at(0, 0)] = c00 * r;
  inv[at(1, 0)] = inv[at(0, 1)] = c10 * r;
  inv[at(2, 0)] = inv[at(0, 2)] = c20 * r;
  inv[at(1, 1)] = c11 * r;
  inv[at(2, 1)] = inv[at(1, 2)] = c21 * r;
  inv[at(2, 2)] = c22 * r;
}

// out = x m.
[[gnu::always_inline]] inline void times(const double* x, const double* m, double* out) {
#pragma GCC unroll 3
  for (int c = 0; c < 3; ++c) {
#pragma GCC unroll 3
    for (int r = 0; r < 3; ++r) {
      out[at(r, c)] = x[at(r, 0)] * m[at(0, c)] + x[at(r, 1)] * m[at(1, c)] + x[at(r, 2)] * m[at(2, c)];
    }
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

// s -= y z^T on the lower triangle of s (the upper one is not read), y z^T symmetric.
[[gnu::always_inline]] inline void subtract_product_lower(double* s, const double* y, const double* z) {
#pragma GCC unroll 3
  for (int c = 0; c < 3; ++c) {
#pragma GCC unroll 3
    for (int r = c; r < 3; ++r) {
      s[at(r, c)] -= y[at(r, 0)] * z[at(c, 0)] + y[at(r, 1)] * z[at(c, 1)] + y[at(r, 2)] * z[at(c, 2)];
    }
  }
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
  // A = L D L^T with unit diagonal blocks in L. With C2 = A(i, i-2) and C1 = L(i, i-1) D(i-1):
  //   L(i, i-2) = C2 D(i-2)^-1
  //   C1 = A(i, i-1) - C2 L(i-1, i-2)^T,  L(i, i-1) = C1 D(i-1)^-1
  //   D(i) = A(i, i) - L(i, i-2) C2^T - L(i, i-1) C1^T
  // Row i waits on D(i-1)^-1 only through two block products and one 3x3 inverse (a single
  // division), where a Cholesky pivot chain has three square roots and divisions in turn.
  const std::size_t first_node = first_;
  bool ok = true;
  for (std::size_t i = from; i < n_; ++i) {
    Block s = block(i, i);
    Block& l2 = l2_[i];
    Block& l1 = l1_[i];
    l2 = Block{};
    l1 = Block{};
    if (i >= first_node + 2) {
      times(block(i, i - 2).v, dinv_[i - 2].v, l2.v);
      subtract_product_lower(s.v, l2.v, block(i, i - 2).v);
    }
    if (i >= first_node + 1) {
      Block c1 = block(i, i - 1);
      if (i >= first_node + 2) subtract_product_transposed(c1.v, block(i, i - 2).v, l1_[i - 1].v);
      times(c1.v, dinv_[i - 1].v, l1.v);
      subtract_product_lower(s.v, l1.v, c1.v);
    }
    inverse_symmetric(s.v, dinv_[i].v, ok);
  }
  return ok;
}

void BandedCholesky::solve(double* v) const {
  // Forward: L y = v (unit diagonal blocks), each y carried in registers for the next two
  // rows; v keeps D^-1 y.
  double a0 = 0.0, a1 = 0.0, a2 = 0.0;  // y(i-1)
  double b0 = 0.0, b1 = 0.0, b2 = 0.0;  // y(i-2)
  for (std::size_t i = first_; i < n_; ++i) {
    double* vi = v + 3 * i;
    const double* p = l1_[i].v;  // zero in the first row
    const double* q = l2_[i].v;  // zero in the first two rows
    const double r0 = vi[0] - (p[at(0, 0)] * a0 + p[at(0, 1)] * a1 + p[at(0, 2)] * a2) -
                      (q[at(0, 0)] * b0 + q[at(0, 1)] * b1 + q[at(0, 2)] * b2);
    const double r1 = vi[1] - (p[at(1, 0)] * a0 + p[at(1, 1)] * a1 + p[at(1, 2)] * a2) -
                      (q[at(1, 0)] * b0 + q[at(1, 1)] * b1 + q[at(1, 2)] * b2);
    const double r2 = vi[2] - (p[at(2, 0)] * a0 + p[at(2, 1)] * a1 + p[at(2, 2)] * a2) -
                      (q[at(2, 0)] * b0 + q[at(2, 1)] * b1 + q[at(2, 2)] * b2);
    const double* m = dinv_[i].v;
    vi[0] = m[at(0, 0)] * r0 + m[at(0, 1)] * r1 + m[at(0, 2)] * r2;
    vi[1] = m[at(1, 0)] * r0 + m[at(1, 1)] * r1 + m[at(1, 2)] * r2;
    vi[2] = m[at(2, 0)] * r0 + m[at(2, 1)] * r1 + m[at(2, 2)] * r2;
    b0 = a0, b1 = a1, b2 = a2;
    a0 = r0, a1 = r1, a2 = r2;
  }
  // Backward: L^T x = D^-1 y.
  a0 = a1 = a2 = 0.0;  // x(i+1)
  b0 = b1 = b2 = 0.0;  // x(i+2)
  for (std::size_t i = n_; i-- > first_;) {
    double* vi = v + 3 * i;
    double r0 = vi[0], r1 = vi[1], r2 = vi[2];
    if (i + 1 < n_) {
      const double* p = l1_[i + 1].v;
      r0 -= p[at(0, 0)] * a0 + p[at(1, 0)] * a1 + p[at(2, 0)] * a2;
      r1 -= p[at(0, 1)] * a0 + p[at(1, 1)] * a1 + p[at(2, 1)] * a2;
      r2 -= p[at(0, 2)] * a0 + p[at(1, 2)] * a1 + p[at(2, 2)] * a2;
    }
    if (i + 2 < n_) {
      const double* q = l2_[i + 2].v;
      r0 -= q[at(0, 0)] * b0 + q[at(1, 0)] * b1 + q[at(2, 0)] * b2;
      r1 -= q[at(0, 1)] * b0 + q[at(1, 1)] * b1 + q[at(2, 1)] * b2;
      r2 -= q[at(0, 2)] * b0 + q[at(1, 2)] * b1 + q[at(2, 2)] * b2;
    }
    vi[0] = r0, vi[1] = r1, vi[2] = r2;
    b0 = a0, b1 = a1, b2 = a2;
    a0 = r0, a1 = r1, a2 = r2;
  }
}

}  // namespace cathbox::tool
