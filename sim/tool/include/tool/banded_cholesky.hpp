#pragma once
// The rod's symmetric positive definite system: 3x3 blocks, one block row per node, coupling
// nodes at most two apart (the bending stencil), so the lower half is three blocks a row:
// A(i, i), A(i, i-1), A(i, i-2). The block Cholesky factorisation of a trailing block
// [first, n) (the rod's free nodes follow its prescribed ones, so one assembly serves the solve
// and the force law's Schur complement) is kept apart from the assembled matrix, which stays
// intact: a factored system can be amended and factored again without a saved copy.
//
// Fixed 3x3 block products have the instruction-level parallelism a scalar band Cholesky lacks
// (its dot products are chains of dependent multiply-adds): same arithmetic, several times
// faster (bench/tool).
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

#include <glm/mat3x3.hpp>

namespace cathbox::tool {

class BandedCholesky {
 public:
  static constexpr std::size_t kBlockBand = 2;  // blocks (i, j) with |i - j| <= 2 are kept

  explicit BandedCholesky(std::size_t max_nodes);

  // Sizes the matrix to `nodes` block rows without touching the blocks (set_row writes them).
  void resize(std::size_t nodes) { n_ = nodes; }
  // Writes block row a: A(a, a), A(a, a-1), A(a, a-2) (the last two ignored where a < 2).
  void set_row(std::size_t a, const glm::dmat3& diag, const glm::dmat3& sub1, const glm::dmat3& sub2) {
    Block* row = &a_[(kBlockBand + 1) * a];
    std::memcpy(row[0].v, &diag[0][0], sizeof(Block));
    std::memcpy(row[1].v, &sub1[0][0], sizeof(Block));
    std::memcpy(row[2].v, &sub2[0][0], sizeof(Block));
  }
  // Adds m (glm's column-major layout: m[column][row]) to block (a, b), a >= b, a - b <= 2.
  // Diagonal blocks are symmetric; only their lower triangle is read by the factorisation.
  void add_block(std::size_t a, std::size_t b, const glm::dmat3& m) {
    Block& dst = block_ref(a, b);
    const double* src = &m[0][0];
#pragma GCC unroll 9
    for (int e = 0; e < 9; ++e) dst.v[e] += src[e];
  }
  // Entry (i, j) of the assembled matrix, by unknown (3 per node), in either order.
  [[nodiscard]] double get(std::size_t i, std::size_t j) const;
  // y += A * x over the unknowns' rows [row_first, row_last) and columns [col_first, col_last).
  void multiply_add(const double* x, double* y, std::size_t row_first, std::size_t row_last,
                    std::size_t col_first, std::size_t col_last) const;

  // Factors the block rows [first_node, n); the assembled matrix is left as it was.
  // Non-positive pivots are clamped (returns false then).
  bool factor(std::size_t first_node);
  // Factors again from block row `from` on (>= the last factor's first node), when since that
  // factorisation only blocks in rows `from` and later changed: rows before it depend on none
  // of them, so the result is factor()'s bit for bit (a contact joining the active set changes
  // one diagonal block). Returns false if a pivot from `from` on was clamped.
  bool refactor_from(std::size_t from);
  // Solves the factored block for b, by unknown (entries [3 first_node, 3 n)), in place.
  void solve(double* b) const;
  // solve(), keeping the forward pass (L y = b) for solve_again.
  void solve_keeping(double* b);
  // solve() of a right-hand side equal to the last kept one's in block rows before `same` (on a
  // factor refactored since only from rows at or after it, or not at all): those rows of the
  // forward pass are the kept ones, bit for bit, and are not computed again (the Newton step
  // solved again with the contact planes it would cross: rod_edge_contact.cpp). Keeps its own.
  void solve_again(double* b, std::size_t same);

  [[nodiscard]] std::size_t nodes() const { return n_; }

  // Work done since construction (bench/tool's deterministic counters): factorisations (whole
  // or from a row), the block rows they factored, solves.
  struct Work {
    std::uint64_t factors = 0, rows_factored = 0, solves = 0;
  };
  [[nodiscard]] const Work& work() const { return work_; }

 private:
  // A 3x3 block, column-major like glm (v[3 column + row]); plain doubles so that the fixed
  // loops below unroll (glm's indexed access goes through a switch).
  struct Block {
    double v[9];
  };
  static_assert(sizeof(glm::dmat3) == sizeof(Block));

  Block& block_ref(std::size_t a, std::size_t b) { return a_[(kBlockBand + 1) * a + (a - b)]; }
  [[nodiscard]] const Block& block(std::size_t a, std::size_t b) const {
    return a_[(kBlockBand + 1) * a + (a - b)];
  }

  bool factor_rows(std::size_t from);
  void forward(double* v, std::size_t from) const;   // L y = v in place, rows [from, n)
  void backward(double* v) const;                    // L^T x = y in place

  std::size_t n_ = 0;
  std::size_t first_ = 0;
  std::vector<Block> a_;     // assembled lower blocks, kBlockBand + 1 per block row
  std::vector<Block> l1_;    // factor L(i, i-1)
  std::vector<Block> l2_;    // factor L(i, i-2)
  std::vector<Block> dinv_;  // inverse of the lower-triangular diagonal factor L(i, i)
  // The last kept forward pass (by unknown), valid in block rows [first_, kept_rows_): a
  // factorisation from a row lowers it.
  std::vector<double> kept_;
  std::size_t kept_rows_ = 0;
  mutable Work work_;
};

}  // namespace cathbox::tool
