#include "rodcore/block_band.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "rodcore/error.hpp"

namespace rodcore {
namespace {

using Block = CyclicBlockBand::Block;
using Vec6 = Eigen::Matrix<double, 6, 1>;

// 2^-64: a fill column below this fraction of the fill's largest entry is zero to
// round-off (block_band.hpp).
const double kDropFill = std::ldexp(1.0, -64);

// L^-1 of the Cholesky factor L L^T of an SPD 6 x 6 block, written out (a fixed-size
// factorisation and inversion by substitution); false if the block is not SPD.
bool pivot_inverse(const Block& D, Block& Linv) {
  double L[6][6] = {};
  for (int j = 0; j < 6; ++j) {
    double d = D(j, j);
    for (int k = 0; k < j; ++k) d -= L[j][k] * L[j][k];
    if (!(d > 0.0) || !std::isfinite(d)) return false;
    L[j][j] = std::sqrt(d);
    const double inv = 1.0 / L[j][j];
    for (int i = j + 1; i < 6; ++i) {
      double v = D(i, j);
      for (int k = 0; k < j; ++k) v -= L[i][k] * L[j][k];
      L[i][j] = v * inv;
    }
  }
  Linv.setZero();
  for (int c = 0; c < 6; ++c) {  // column c of L^-1: forward substitution of e_c
    Linv(c, c) = 1.0 / L[c][c];
    for (int i = c + 1; i < 6; ++i) {
      double v = 0.0;
      for (int k = c; k < i; ++k) v -= L[i][k] * Linv(k, c);
      Linv(i, c) = v / L[i][i];
    }
  }
  return true;
}

}  // namespace

CyclicBlockBand::CyclicBlockBand(std::size_t N, int b) : N_(N), n1_(0), b_(b) {
  if (b < 1 || N < 2 * static_cast<std::size_t>(b) + 1)
    throw InputError("CyclicBlockBand: " + std::to_string(N) + " blocks of half-bandwidth " +
                     std::to_string(b) +
                     ": a cyclic band needs b >= 1 and N >= 2 b + 1 (else blocks couple both ways round)");
  n1_ = N - static_cast<std::size_t>(b);
  const std::size_t w = static_cast<std::size_t>(b) + 1;
  A_.assign(N * w, Block::Zero());
  L_.assign(n1_ * w, Block::Zero());
  Linv_.assign(n1_, Block::Zero());
  W_.assign(n1_ * static_cast<std::size_t>(b), Block::Zero());
  Wlive_.assign(n1_, 1);
  S_.resize(6 * b, 6 * b);
}

void CyclicBlockBand::set_zero() { std::fill(A_.begin(), A_.end(), Block::Zero()); }

Block CyclicBlockBand::A_at(std::size_t i, std::size_t j) const {
  const std::size_t d = (i + N_ - j) % N_;
  const std::size_t b = static_cast<std::size_t>(b_);
  if (d <= b) return lower(i, static_cast<int>(d));
  if (N_ - d <= b) return lower(j, static_cast<int>(N_ - d)).transpose();
  return Block::Zero();
}

bool CyclicBlockBand::factorise() {
  ok_ = false;
  const std::size_t b = static_cast<std::size_t>(b_), w = b + 1, n1 = n1_;
  auto L = [&](std::size_t j, std::size_t d) -> Block& { return L_[j * w + d]; };
  // The interior band: L(j, c) = (A(j, c) - sum_l L(j, l) L(c, l)^T) L(c, c)^-T.
  for (std::size_t j = 0; j < n1; ++j) {
    const std::size_t lo = j >= b ? j - b : 0;
    for (std::size_t c = lo; c < j; ++c) {
      Block X = lower(j, static_cast<int>(j - c));
      for (std::size_t l = lo; l < c; ++l) X.noalias() -= L(j, j - l) * L(c, c - l).transpose();
      L(j, j - c).noalias() = X * Linv_[c].transpose();
    }
    Block D = lower(j, 0);
    for (std::size_t l = lo; l < j; ++l) D.noalias() -= L(j, j - l) * L(j, j - l).transpose();
    if (!pivot_inverse(D, Linv_[j])) return false;
  }
  // The border rows W = A21 L11^-T, column by column (all b border blocks at once).
  auto Wb = [&](std::size_t k, std::size_t j) -> Block& { return W_[j * b + k]; };
  double biggest = 0.0;
  std::size_t quiet = 0;               // consecutive columns below kDropFill of the biggest
  const std::size_t restart = n1 - b;  // from here the band couples to the border directly
  fill_columns_ = 0;
  for (std::size_t j = 0; j < n1; ++j) {
    if (quiet >= b && j >= b && j < restart) {
      Wlive_[j] = 0;
      continue;
    }
    Wlive_[j] = 1;
    ++fill_columns_;
    const std::size_t lo = j >= b ? j - b : 0;
    double col = 0.0;
    for (std::size_t k = 0; k < b; ++k) {
      Block X = A_at(n1 + k, j);
      for (std::size_t l = lo; l < j; ++l)
        if (Wlive_[l]) X.noalias() -= Wb(k, l) * L(j, j - l).transpose();
      Wb(k, j).noalias() = X * Linv_[j].transpose();
      col = std::max(col, Wb(k, j).cwiseAbs().maxCoeff());
    }
    biggest = std::max(biggest, col);
    quiet = col <= kDropFill * biggest ? quiet + 1 : 0;
  }
  // The border's Schur complement S = A22 - W W^T and its Cholesky factor.
  std::vector<Block> acc(b * b, Block::Zero());
  for (std::size_t j = 0; j < n1; ++j) {
    if (!Wlive_[j]) continue;
    for (std::size_t k1 = 0; k1 < b; ++k1)
      for (std::size_t k2 = 0; k2 <= k1; ++k2)
        acc[k1 * b + k2].noalias() += Wb(k1, j) * Wb(k2, j).transpose();
  }
  for (std::size_t k1 = 0; k1 < b; ++k1)
    for (std::size_t k2 = 0; k2 <= k1; ++k2) {
      const Block s = A_at(n1 + k1, n1 + k2) - acc[k1 * b + k2];
      S_.block<6, 6>(6 * k1, 6 * k2) = s;
      S_.block<6, 6>(6 * k2, 6 * k1) = s.transpose();
    }
  S_llt_.compute(S_);
  if (S_llt_.info() != Eigen::Success || !S_llt_.matrixLLT().allFinite()) return false;
  ok_ = true;
  return true;
}

void CyclicBlockBand::solve(double* x) const {
  if (!ok_) throw NumericalError("CyclicBlockBand::solve: no successful factorise()");
  const std::size_t b = static_cast<std::size_t>(b_), w = b + 1, n1 = n1_;
  auto X = [x](std::size_t j) { return Eigen::Map<Vec6>(x + 6 * j); };
  auto L = [&](std::size_t j, std::size_t d) -> const Block& { return L_[j * w + d]; };
  auto Wb = [&](std::size_t k, std::size_t j) -> const Block& { return W_[j * b + k]; };
  // forward: L11 y1 = x1, then the border S x2 = x2 - W y1
  for (std::size_t j = 0; j < n1; ++j) {
    Vec6 v = X(j);
    for (std::size_t l = j >= b ? j - b : 0; l < j; ++l) v.noalias() -= L(j, j - l) * X(l);
    X(j).noalias() = Linv_[j] * v;
  }
  Eigen::Map<Eigen::VectorXd> x2(x + 6 * n1, static_cast<Eigen::Index>(6 * b));
  for (std::size_t j = 0; j < n1; ++j) {
    if (!Wlive_[j]) continue;
    const Vec6 yj = X(j);
    for (std::size_t k = 0; k < b; ++k)
      x2.segment<6>(static_cast<Eigen::Index>(6 * k)).noalias() -= Wb(k, j) * yj;
  }
  S_llt_.solveInPlace(x2);
  // backward: L11^T x1 = y1 - W^T x2
  for (std::size_t j = n1; j-- > 0;) {
    Vec6 v = X(j);
    for (std::size_t i = j + 1; i <= std::min(j + b, n1 - 1); ++i)
      v.noalias() -= L(i, i - j).transpose() * X(i);
    if (Wlive_[j])
      for (std::size_t k = 0; k < b; ++k)
        v.noalias() -= Wb(k, j).transpose() * x2.segment<6>(static_cast<Eigen::Index>(6 * k));
    X(j).noalias() = Linv_[j].transpose() * v;
  }
}

}  // namespace rodcore
