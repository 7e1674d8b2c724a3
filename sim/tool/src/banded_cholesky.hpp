#pragma once
// A symmetric positive definite band matrix (lower half stored) with an in-place Cholesky
// factorisation restricted to a trailing block [first, n): the rod's free unknowns follow its
// prescribed ones, so one assembly serves the solve and the force law's Schur complement.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace cathbox::tool {

class BandedCholesky {
 public:
  BandedCholesky(std::size_t max_n, std::size_t half_band) : band_(half_band) {
    a_.assign(max_n * (half_band + 1), 0.0);
    saved_.reserve(a_.size());
    inv_diag_.assign(max_n, 0.0);
  }

  void reset(std::size_t n);
  // Adds v to entry (i, j); only |i - j| <= half_band is kept, i and j in any order.
  void add(std::size_t i, std::size_t j, double v) {
    if (i < j) {
      const std::size_t t = i;
      i = j;
      j = t;
    }
    a_[i * (band_ + 1) + (i - j)] += v;
  }
  // Adds a 3x3 block (column-major, as glm stores it) at rows 3a.., columns 3b.. with a >= b;
  // on the diagonal (a == b) only the lower triangle is added.
  void add_block(std::size_t a, std::size_t b, const double* m) {
    const std::size_t w = band_ + 1;
    double* base = &a_[3 * a * w];
    const std::size_t off = 3 * (a - b);
    if (a == b) {
      base[0] += m[0];
      base[w + 1] += m[1];
      base[w] += m[4];
      base[2 * w + 2] += m[2];
      base[2 * w + 1] += m[5];
      base[2 * w] += m[8];
      return;
    }
    for (std::size_t r = 0; r < 3; ++r) {
      double* row = base + r * w + off + r;
      row[0] += m[r];
      row[-1] += m[3 + r];
      row[-2] += m[6 + r];
    }
  }
  [[nodiscard]] double get(std::size_t i, std::size_t j) const {
    if (i < j) return get(j, i);
    if (i - j > band_) return 0.0;
    return a_[i * (band_ + 1) + (i - j)];
  }
  // y += A * x over the rows [row_first, row_last) and the columns [col_first, col_last).
  void multiply_add(const double* x, double* y, std::size_t row_first, std::size_t row_last,
                    std::size_t col_first, std::size_t col_last) const;

  // Keeps a copy of the assembled matrix / puts it back (to amend it after a factorisation).
  void save() { saved_.assign(a_.begin(), a_.begin() + static_cast<std::ptrdiff_t>(n_ * (band_ + 1))); }
  void restore() { std::copy(saved_.begin(), saved_.end(), a_.begin()); }

  // Factors the block [first, n) in place; non-positive pivots are clamped (returns false then).
  bool factor(std::size_t first);
  // Solves the factored block for b (entries [first, n)), in place.
  void solve(double* b) const;

  [[nodiscard]] std::size_t size() const { return n_; }
  [[nodiscard]] std::size_t half_band() const { return band_; }

 private:
  std::size_t band_;
  std::size_t n_ = 0;
  std::size_t first_ = 0;
  std::vector<double> a_;
  std::vector<double> saved_;
  std::vector<double> inv_diag_;  // 1 / L(i, i) of the factored block
};

}  // namespace cathbox::tool
