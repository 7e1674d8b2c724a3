#include "tool/banded_cholesky.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace cathbox::tool {
namespace {

// Blocks are column-major: entry (row r, column c) is v[3 c + r].
constexpr int at(int r, int c) { return 3 * c + r; }

// Lower-triangular Cholesky factor of the symmetric s (its lower triangle), inverted.
// A pivot that is not positive is clamped to 1e-12 and reported.
[[gnu::always_inline]] inline void inverse_cholesky(const double* s, double* inv, bool& ok) {
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
  inv[at(0, 0)] = i00;
  inv[at(1, 0)] = i10;
  inv[at(2, 0)] = i20;
  inv[at(0, 1)] = 0.0;
  inv[at(1, 1)] = i11;
  inv[at(2, 1)] = i21;
  inv[at(0, 2)] = 0.0;
  inv[at(1, 2)] = 0.0;
  inv[at(2, 2)] = i22;
}

// out = x M^T for a lower-triangular M.
[[gnu::always_inline]] inline void times_lower_transposed(const double* x, const double* m, double* out) {
#pragma GCC unroll 3
  for (int r = 0; r < 3; ++r) {
    out[at(r, 0)] = x[at(r, 0)] * m[at(0, 0)];
    out[at(r, 1)] = x[at(r, 0)] * m[at(1, 0)] + x[at(r, 1)] * m[at(1, 1)];
    out[at(r, 2)] = x[at(r, 0)] * m[at(2, 0)] + x[at(r, 1)] * m[at(2, 1)] + x[at(r, 2)] * m[at(2, 2)];
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

// s -= x x^T on the lower triangle of s (the upper one is not read).
[[gnu::always_inline]] inline void subtract_gram_lower(double* s, const double* x) {
#pragma GCC unroll 3
  for (int c = 0; c < 3; ++c) {
#pragma GCC unroll 3
    for (int r = c; r < 3; ++r) {
      s[at(r, c)] -= x[at(r, 0)] * x[at(c, 0)] + x[at(r, 1)] * x[at(c, 1)] + x[at(r, 2)] * x[at(c, 2)];
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
  if (first_node != first_) kept_rows_ = 0;
  first_ = first_node;
  return factor_rows(first_node);
}

bool BandedCholesky::refactor_from(std::size_t from) { return factor_rows(std::max(from, first_)); }

bool BandedCholesky::factor_rows(std::size_t from) {
  const std::size_t first_node = first_;
  bool ok = true;
  ++work_.factors;
  kept_rows_ = std::min(kept_rows_, from);
  work_.rows_factored += n_ > from ? n_ - from : 0;
  for (std::size_t i = from; i < n_; ++i) {
    // L(i, i-2) = A(i, i-2) L(i-2, i-2)^-T
    // L(i, i-1) = (A(i, i-1) - L(i, i-2) L(i-1, i-2)^T) L(i-1, i-1)^-T
    // L(i, i) L(i, i)^T = A(i, i) - L(i, i-2) L(i, i-2)^T - L(i, i-1) L(i, i-1)^T
    Block s = block(i, i);
    Block& c = l2_[i];
    Block& b = l1_[i];
    c = Block{};
    b = Block{};
    if (i >= first_node + 2) {
      times_lower_transposed(block(i, i - 2).v, dinv_[i - 2].v, c.v);
      subtract_gram_lower(s.v, c.v);
    }
    if (i >= first_node + 1) {
      Block t = block(i, i - 1);
      if (i >= first_node + 2) subtract_product_transposed(t.v, c.v, l1_[i - 1].v);
      times_lower_transposed(t.v, dinv_[i - 1].v, b.v);
      subtract_gram_lower(s.v, b.v);
    }
    inverse_cholesky(s.v, dinv_[i].v, ok);
  }
  return ok;
}

void BandedCholesky::solve(double* v) const {
  ++work_.solves;
  forward(v, first_);
  backward(v);
}

void BandedCholesky::solve_keeping(double* v) {
  ++work_.solves;
  forward(v, first_);
  kept_.assign(v + 3 * first_, v + 3 * n_);
  kept_rows_ = n_;
  backward(v);
}

void BandedCholesky::solve_again(double* v, std::size_t same) {
  ++work_.solves;
  const std::size_t from = std::max(first_, std::min({same, kept_rows_, n_}));
  std::copy(kept_.begin(), kept_.begin() + static_cast<std::ptrdiff_t>(3 * (from - first_)), v + 3 * first_);
  forward(v, from);
  kept_.resize(3 * (n_ - first_));
  std::copy(v + 3 * from, v + 3 * n_, kept_.begin() + static_cast<std::ptrdiff_t>(3 * (from - first_)));
  kept_rows_ = n_;
  backward(v);
}

// Forward: L y = v, from block row `from` on (the rows before it hold y already).
void BandedCholesky::forward(double* v, std::size_t from) const {
  for (std::size_t i = from; i < n_; ++i) {
    double r[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    if (i >= first_ + 1) subtract_times(r, l1_[i].v, v + 3 * (i - 1));
    if (i >= first_ + 2) subtract_times(r, l2_[i].v, v + 3 * (i - 2));
    const double* m = dinv_[i].v;  // lower triangular
    v[3 * i] = m[at(0, 0)] * r[0];
    v[3 * i + 1] = m[at(1, 0)] * r[0] + m[at(1, 1)] * r[1];
    v[3 * i + 2] = m[at(2, 0)] * r[0] + m[at(2, 1)] * r[1] + m[at(2, 2)] * r[2];
  }
}

// Backward: L^T x = y.
void BandedCholesky::backward(double* v) const {
  for (std::size_t i = n_; i-- > first_;) {
    double r[3] = {v[3 * i], v[3 * i + 1], v[3 * i + 2]};
    if (i + 1 < n_) subtract_transposed_times(r, l1_[i + 1].v, v + 3 * (i + 1));
    if (i + 2 < n_) subtract_transposed_times(r, l2_[i + 2].v, v + 3 * (i + 2));
    const double* m = dinv_[i].v;  // L(i, i)^-T is upper triangular
    v[3 * i] = m[at(0, 0)] * r[0] + m[at(1, 0)] * r[1] + m[at(2, 0)] * r[2];
    v[3 * i + 1] = m[at(1, 1)] * r[1] + m[at(2, 1)] * r[2];
    v[3 * i + 2] = m[at(2, 2)] * r[2];
  }
}

}  // namespace cathbox::tool
