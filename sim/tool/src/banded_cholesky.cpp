#include "banded_cholesky.hpp"

#include <algorithm>
#include <cmath>

namespace cathbox::tool {

void BandedCholesky::reset(std::size_t n) {
  n_ = n;
  std::fill(a_.begin(), a_.begin() + static_cast<std::ptrdiff_t>(n * (band_ + 1)), 0.0);
}

void BandedCholesky::multiply_add(const double* x, double* y, std::size_t row_first,
                                  std::size_t row_last, std::size_t col_first,
                                  std::size_t col_last) const {
  for (std::size_t i = row_first; i < row_last; ++i) {
    const std::size_t lo = std::max(col_first, i > band_ ? i - band_ : 0);
    const std::size_t hi = std::min(col_last, i + band_ + 1);
    double sum = 0.0;
    for (std::size_t j = lo; j < hi; ++j) sum += get(i, j) * x[j];
    y[i] += sum;
  }
}

bool BandedCholesky::factor(std::size_t first) {
  first_ = first;
  bool ok = true;
  const std::size_t w = band_ + 1;
  for (std::size_t i = first; i < n_; ++i) {
    const std::size_t j0 = std::max(first, i > band_ ? i - band_ : 0);
    double* row_i = &a_[i * w];
    for (std::size_t j = j0; j <= i; ++j) {
      const double* row_j = &a_[j * w];
      double sum = row_i[i - j];
      const std::size_t k0 = std::max(j0, j > band_ ? j - band_ : 0);
      for (std::size_t k = k0; k < j; ++k) sum -= row_i[i - k] * row_j[j - k];
      if (j == i) {
        if (!(sum > 1e-300)) {
          ok = false;
          sum = 1e-12;
        }
        row_i[0] = std::sqrt(sum);
        inv_diag_[i] = 1.0 / row_i[0];
      } else {
        row_i[i - j] = sum * inv_diag_[j];
      }
    }
  }
  return ok;
}

void BandedCholesky::solve(double* b) const {
  const std::size_t w = band_ + 1;
  for (std::size_t i = first_; i < n_; ++i) {
    const std::size_t j0 = std::max(first_, i > band_ ? i - band_ : 0);
    double sum = b[i];
    for (std::size_t j = j0; j < i; ++j) sum -= a_[i * w + (i - j)] * b[j];
    b[i] = sum * inv_diag_[i];
  }
  for (std::size_t ii = n_; ii-- > first_;) {
    double sum = b[ii];
    const std::size_t j1 = std::min(n_, ii + band_ + 1);
    for (std::size_t j = ii + 1; j < j1; ++j) sum -= a_[j * w + (j - ii)] * b[j];
    b[ii] = sum * inv_diag_[ii];
  }
}

}  // namespace cathbox::tool
