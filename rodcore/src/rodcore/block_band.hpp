// Cholesky of a symmetric positive definite matrix of 6 x 6 blocks that is
// cyclic block-banded: block i couples to block j only when their cyclic
// distance min(|i - j|, N - |i - j|) is <= b (the implicit matrix of the
// overdamped rod, Z + dt D^T K D, with d/ds the fd4 stencil: b = 4;
// brownian.hpp).
//
// The last b blocks are the border, the first n1 = N - b the interior. The
// interior has no wrapped couplings (for N >= 2b + 1) and is a plain band:
//   A = [[A11, A12], [A21, A22]],  A11 = L11 L11^T  (banded, half-bandwidth b),
//   W = A21 L11^-T  (dense b x n1 blocks: the corner couples the border to the
//                    interior's first b blocks, and the fill runs along it),
//   S = A22 - W W^T = L22 L22^T  (6b x 6b, dense).
// O(N b^2) fixed-size 6 x 6 block operations. The fill W decays along the
// interior like the implicit matrix's inverse (over a few points for the DNA
// ring at 100 ps): once b consecutive columns of W are below 2^-64 of its
// largest block entry, W is a homogeneous recurrence of them, and the columns
// after them are dropped until the band couples to the border again (the last
// b interior blocks): a change far below round-off (the dropped part of S is
// below 2^-128 of it), and the full fill where W does not decay.
#pragma once
#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstddef>
#include <vector>

namespace rodcore {

class CyclicBlockBand {
 public:
  using Block = Eigen::Matrix<double, 6, 6>;
  // N blocks, half-bandwidth b >= 1; N >= 2b + 1 (else every pair of blocks
  // would couple both ways round: InputError naming N and b).
  CyclicBlockBand(std::size_t N, int b);

  std::size_t blocks() const { return N_; }
  int bandwidth() const { return b_; }

  // The lower blocks: lower(i, d) = A(i, i - d mod N), d = 0..b (lower(i, 0)
  // the diagonal block, symmetric); A(i - d, i) = lower(i, d)^T.
  Block& lower(std::size_t i, int d) { return A_[i * (b_ + 1) + d]; }
  const Block& lower(std::size_t i, int d) const { return A_[i * (b_ + 1) + d]; }
  void set_zero();

  // Factorises the blocks set; false if the matrix is not positive definite
  // (a pivot block or the border's Schur complement failed), then solve() is
  // not allowed.
  bool factorise();
  // x <- A^-1 x (6 N values, block i at 6 i).
  void solve(double* x) const;

  // Columns of the fill W computed at the last factorise() (n1 when none was
  // dropped).
  std::size_t fill_columns() const { return fill_columns_; }

 private:
  Block A_at(std::size_t i, std::size_t j) const;  // any block (zero outside the band)
  std::size_t N_, n1_;
  int b_;
  std::vector<Block> A_;     // N (b + 1) lower blocks
  std::vector<Block> L_;     // interior factor: L(j, j - d), d = 1..b (d = 0 unused)
  std::vector<Block> Linv_;  // inverse of the diagonal factor blocks L(j, j)
  std::vector<Block> W_;     // border rows: W(k, j) at j * b + k
  std::vector<char> Wlive_;  // column j of W computed (else zero)
  Eigen::MatrixXd S_;        // border Schur complement A22 - W W^T
  Eigen::LLT<Eigen::MatrixXd> S_llt_;
  std::size_t fill_columns_ = 0;
  bool ok_ = false;
};

}  // namespace rodcore
