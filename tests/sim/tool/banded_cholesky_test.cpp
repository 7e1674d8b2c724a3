// The rod's block-band solver against a dense Cholesky solve of the same matrix.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include <glm/geometric.hpp>
#include <glm/mat3x3.hpp>
#include <glm/matrix.hpp>
#include <gtest/gtest.h>

#include "tool/banded_cholesky.hpp"

namespace {

using cathbox::tool::BandedCholesky;

struct Dense {
  std::size_t n;
  std::vector<double> a;  // row-major n x n
  double& at(std::size_t i, std::size_t j) { return a[i * n + j]; }
};

glm::dmat3 random_block(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  glm::dmat3 m;
  for (int c = 0; c < 3; ++c) {
    for (int r = 0; r < 3; ++r) m[c][r] = u(rng);
  }
  return m;
}

// A random symmetric positive definite matrix with blocks coupling nodes at most two apart,
// assembled into both the band solver (as the rod does: set_row, then add_block) and a dense copy.
Dense build(BandedCholesky& band, std::size_t nodes, std::mt19937& rng) {
  Dense d{3 * nodes, std::vector<double>(9 * nodes * nodes, 0.0)};
  std::vector<glm::dmat3> sub1(nodes, glm::dmat3(0.0)), sub2(nodes, glm::dmat3(0.0)), diag(nodes);
  for (std::size_t k = 0; k < nodes; ++k) {
    if (k >= 1) sub1[k] = random_block(rng);
    if (k >= 2) sub2[k] = random_block(rng);
  }
  for (std::size_t k = 0; k < nodes; ++k) {
    const glm::dmat3 s = random_block(rng);
    diag[k] = s + glm::transpose(s) + glm::dmat3(20.0);  // diagonally dominant: SPD
  }
  band.resize(nodes);
  for (std::size_t k = 0; k < nodes; ++k) band.set_row(k, diag[k] * 0.5, sub1[k], sub2[k]);
  for (std::size_t k = 0; k < nodes; ++k) band.add_block(k, k, diag[k] * 0.5);
  for (std::size_t k = 0; k < nodes; ++k) {
    for (int c = 0; c < 3; ++c) {
      for (int r = 0; r < 3; ++r) {
        d.at(3 * k + r, 3 * k + c) = diag[k][c][r];
        if (k >= 1) d.at(3 * k + r, 3 * (k - 1) + c) = d.at(3 * (k - 1) + c, 3 * k + r) = sub1[k][c][r];
        if (k >= 2) d.at(3 * k + r, 3 * (k - 2) + c) = d.at(3 * (k - 2) + c, 3 * k + r) = sub2[k][c][r];
      }
    }
  }
  return d;
}

// Solves the trailing block [f, n) of the dense matrix by Gaussian elimination.
std::vector<double> dense_solve(Dense d, std::size_t f, std::vector<double> b) {
  const std::size_t n = d.n;
  for (std::size_t p = f; p < n; ++p) {
    for (std::size_t r = p + 1; r < n; ++r) {
      const double m = d.at(r, p) / d.at(p, p);
      for (std::size_t c = p; c < n; ++c) d.at(r, c) -= m * d.at(p, c);
      b[r] -= m * b[p];
    }
  }
  for (std::size_t p = n; p-- > f;) {
    double s = b[p];
    for (std::size_t c = p + 1; c < n; ++c) s -= d.at(p, c) * b[c];
    b[p] = s / d.at(p, p);
  }
  return b;
}

TEST(BandedCholesky, SolvesTheTrailingBlockLikeADenseSolve) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-5.0, 5.0);
  for (const std::size_t nodes : {1U, 2U, 3U, 8U, 40U}) {
    for (std::size_t first = 0; first < std::min<std::size_t>(nodes, 4); ++first) {
      BandedCholesky band(nodes + 3);
      const Dense d = build(band, nodes, rng);
      std::vector<double> b(3 * nodes);
      for (double& v : b) v = u(rng);
      const std::vector<double> want = dense_solve(d, 3 * first, b);
      ASSERT_TRUE(band.factor(first));
      std::vector<double> got = b;
      band.solve(got.data());
      for (std::size_t i = 3 * first; i < 3 * nodes; ++i) {
        EXPECT_NEAR(got[i], want[i], 1e-10 * (1.0 + std::abs(want[i]))) << nodes << " nodes, first " << first << ", unknown " << i;
      }
      for (std::size_t i = 0; i < 3 * first; ++i) EXPECT_EQ(got[i], b[i]) << "prescribed unknowns untouched";
      // The factorisation leaves the assembled matrix intact.
      for (std::size_t i = 0; i < d.n; ++i) {
        for (std::size_t j = 0; j < d.n; ++j) ASSERT_EQ(band.get(i, j), d.a[i * d.n + j]) << i << "," << j;
      }
    }
  }
}

// A rod's matrix is stiff along its edges (EA / rest ~10^7 mN/mm) and soft across them (drag
// / dt ~5): a chain of axial springs along a wandering tangent, no bending, the first two nodes
// prescribed. The solve must leave a residual at rounding level. An L D L^T form with D's 3x3
// blocks inverted explicitly left 1e-1-1 here (its error along the axis multiplied by the axial
// stiffness twice), where the Cholesky form's Gram products leave ~1e-10.
TEST(BandedCholesky, SolvesAStiffRodChainToRoundingLevel) {
  std::mt19937 rng(5);
  std::normal_distribution<double> gauss(0.0, 1.0);
  for (const double ks : {5.0e6, 1.0e7}) {
    const std::size_t nodes = 60;
    BandedCholesky band(nodes);
    std::vector<glm::dmat3> diag(nodes, glm::dmat3(5.0)), sub1(nodes, glm::dmat3(0.0));
    glm::dvec3 tangent(0.0, 0.0, 1.0);
    for (std::size_t k = 0; k + 1 < nodes; ++k) {
      tangent = glm::normalize(tangent + 0.3 * glm::dvec3(gauss(rng), gauss(rng), gauss(rng)));
      const glm::dmat3 spring = ks * glm::outerProduct(tangent, tangent);
      diag[k] += spring;
      diag[k + 1] += spring;
      sub1[k + 1] -= spring;
    }
    band.resize(nodes);
    for (std::size_t k = 0; k < nodes; ++k) band.set_row(k, diag[k], sub1[k], glm::dmat3(0.0));
    ASSERT_TRUE(band.factor(2));
    std::vector<double> b(3 * nodes);
    for (double& v : b) v = gauss(rng);
    std::vector<double> x = b;
    band.solve(x.data());
    std::vector<double> free_x(3 * nodes, 0.0), ax(3 * nodes, 0.0);
    for (std::size_t i = 6; i < 3 * nodes; ++i) free_x[i] = x[i];
    band.multiply_add(free_x.data(), ax.data(), 6, 3 * nodes, 6, 3 * nodes);
    double residual = 0.0, scale = 0.0;
    for (std::size_t i = 6; i < 3 * nodes; ++i) {
      ASSERT_TRUE(std::isfinite(x[i]));
      residual = std::max(residual, std::abs(ax[i] - b[i]));
      scale = std::max(scale, std::abs(b[i]));
    }
    EXPECT_LT(residual / scale, 1e-8) << "axial stiffness " << ks;
  }
}

// Random systems of 3, 8 and 40 nodes, each factored from `first` (0, 1, 2), with every third
// node from `first` on as the one whose diagonal block a contact changes: fn(band, first,
// changed, b), b a right-hand side.
template <typename Fn>
void for_each_changed_row(unsigned seed, Fn&& fn) {
  std::mt19937 rng(seed);
  for (const std::size_t nodes : {3U, 8U, 40U}) {
    for (std::size_t first = 0; first < 3; ++first) {
      for (std::size_t changed = first; changed < nodes; changed += 3) {
        BandedCholesky band(nodes);
        build(band, nodes, rng);
        ASSERT_TRUE(band.factor(first));
        std::vector<double> b(3 * nodes);
        for (std::size_t i = 0; i < b.size(); ++i) b[i] = std::cos(0.7 * static_cast<double>(i));
        fn(band, first, changed, b);
      }
    }
  }
}

// A contact joining at node `changed`: k n n^T on its diagonal block.
void join_contact(BandedCholesky& band, std::size_t node) {
  const glm::dvec3 normal = glm::normalize(glm::dvec3(0.3, -0.8, 0.5));
  band.add_block(node, node, 2.0e5 * glm::outerProduct(normal, normal));
}

TEST(BandedCholesky, RefactoringFromAChangedDiagonalBlockEqualsAFullFactorisation) {
  for_each_changed_row(5, [](BandedCholesky& band, std::size_t first, std::size_t changed, const std::vector<double>& b) {
    join_contact(band, changed);
    std::vector<double> partial = b;
    ASSERT_TRUE(band.refactor_from(changed));
    band.solve(partial.data());
    std::vector<double> full = b;
    ASSERT_TRUE(band.factor(first));
    band.solve(full.data());
    for (std::size_t i = 0; i < b.size(); ++i) {
      ASSERT_EQ(partial[i], full[i]) << "first " << first << ", changed " << changed << ", unknown " << i;
    }
  });
}

// The Newton step solved again with a contact plane taken at node `changed` (rod_edge_contact.cpp):
// the factor refactored from there and the right-hand side changed from there on; solve_again
// keeps the kept forward pass before it and equals a whole solve bit for bit, twice in a row
// (the second pass keeps the first's) and after a factorisation from an earlier row.
TEST(BandedCholesky, SolvingAgainFromAChangedRowEqualsAWholeSolve) {
  for_each_changed_row(9, [](BandedCholesky& band, std::size_t first, std::size_t changed, const std::vector<double>& b) {
    std::vector<double> plain = b;
    band.solve_keeping(plain.data());
    std::vector<double> again = b, whole = b;
    for (int pass = 0; pass < 3; ++pass) {
      // Pass 2 changes an earlier row than it says: the factorisation from it must count.
      const std::size_t row = pass == 2 ? first : changed;
      join_contact(band, row);
      ASSERT_TRUE(band.refactor_from(row));
      for (std::size_t i = 3 * changed; i < b.size(); ++i) again[i] = whole[i] = b[i] + 0.1 * pass;
      band.solve_again(again.data(), changed);
      std::vector<double> x = whole;
      band.solve(x.data());
      for (std::size_t i = 3 * first; i < b.size(); ++i) {
        ASSERT_EQ(again[i], x[i]) << "first " << first << ", changed " << changed << ", pass " << pass << ", unknown " << i;
      }
      again = whole;
    }
  });
}

TEST(BandedCholesky, MultiplyAddOverABlockOfRowsAndColumns) {
  std::mt19937 rng(11);
  const std::size_t nodes = 12;
  BandedCholesky band(nodes);
  const Dense d = build(band, nodes, rng);
  std::vector<double> x(d.n);
  for (std::size_t i = 0; i < d.n; ++i) x[i] = std::sin(static_cast<double>(i));
  std::vector<double> y(d.n, 1.0);
  band.multiply_add(x.data(), y.data(), 4, 20, 9, 30);
  for (std::size_t i = 0; i < d.n; ++i) {
    double want = 1.0;
    if (i >= 4 && i < 20) {
      for (std::size_t j = 9; j < 30; ++j) want += d.a[i * d.n + j] * x[j];
    }
    EXPECT_NEAR(y[i], want, 1e-12) << i;
  }
}

TEST(BandedCholesky, ReportsAClampedPivot) {
  BandedCholesky band(2);
  band.resize(2);
  band.set_row(0, glm::dmat3(1.0), glm::dmat3(0.0), glm::dmat3(0.0));
  glm::dmat3 singular(1.0);
  singular[1][1] = 0.0;
  band.set_row(1, singular, glm::dmat3(0.0), glm::dmat3(0.0));
  EXPECT_FALSE(band.factor(0));
  std::vector<double> b{1, 2, 3, 4, 5, 6};
  band.solve(b.data());
  for (const double v : b) EXPECT_TRUE(std::isfinite(v));
}

}  // namespace
