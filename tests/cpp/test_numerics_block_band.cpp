// The cyclic block-band Cholesky (rodcore/src/rodcore/block_band.hpp) against
// an independent truth: Eigen's dense LLT of the same matrix, for random
// symmetric positive definite cyclic block-banded matrices (b = 4, as the
// fd4 Brownian step has; N small, N = 2 b + 1 where every pair of blocks
// couples, and the kilobase ring's N = 1050), a slowly decaying fill (weak
// diagonal) where nothing may be dropped, and refusals of what it cannot
// hold. The control: the same solver without the corner blocks (the band of
// an open rod) must give a wrong answer for the ring.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <stdexcept>

#include "rodcore/block_band.hpp"
#include "rodcore/error.hpp"

using rodcore::CyclicBlockBand;
using Block = CyclicBlockBand::Block;

namespace {

// A random SPD cyclic block-banded matrix: B^T B + shift I with B cyclic
// banded of half-bandwidth b / 2 (so B^T B has half-bandwidth b), written
// into the solver's lower blocks and returned dense (built by blocks: O(N)).
// laplacian: B(i, i) = I and B(i, i + 1) = -I + 0.05 R only, so that B^T B + shift I is a
// ring Laplacian whose inverse (and the fill) decays over ~shift^-1/2 blocks.
Eigen::MatrixXd random_band(CyclicBlockBand& band, unsigned seed, double shift, bool corners = true,
                            bool laplacian = false) {
  const std::size_t N = band.blocks();
  const int b = band.bandwidth();
  const int half = b / 2;
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  auto wrap = [N](std::size_t i, int o) {
    return (i + 2 * N + static_cast<std::size_t>(o + static_cast<int>(N))) % N;
  };
  // B(i, wrap(i, o)) for o = -half..half
  std::vector<Block> B(N * static_cast<std::size_t>(b + 1));
  for (auto& blk : B)
    for (int k = 0; k < 36; ++k) blk(k / 6, k % 6) = g(gen);
  if (laplacian)
    for (std::size_t i = 0; i < N; ++i)
      for (int o = -half; o <= half; ++o) {
        Block& blk = B[i * static_cast<std::size_t>(b + 1) + static_cast<std::size_t>(o + half)];
        blk = o == 0   ? Block(Block::Identity())
              : o == 1 ? Block(-Block::Identity() + 0.05 * blk)
                       : Block(Block::Zero());
      }
  const Eigen::Index n = static_cast<Eigen::Index>(6 * N);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t i = 0; i < N; ++i)
    for (int o1 = -half; o1 <= half; ++o1)
      for (int o2 = -half; o2 <= half; ++o2) {
        const Block& B1 = B[i * static_cast<std::size_t>(b + 1) + static_cast<std::size_t>(o1 + half)];
        const Block& B2 = B[i * static_cast<std::size_t>(b + 1) + static_cast<std::size_t>(o2 + half)];
        A.block<6, 6>(6 * wrap(i, o1), 6 * wrap(i, o2)) += B1.transpose() * B2;
      }
  A.diagonal().array() += shift;
  band.set_zero();
  for (std::size_t i = 0; i < N; ++i)
    for (int d = 0; d <= b; ++d) {
      const std::size_t j = wrap(i, -d);
      const bool wraps = j > i;
      band.lower(i, d) = (wraps && !corners) ? Block::Zero() : Block(A.block<6, 6>(6 * i, 6 * j));
    }
  return A;
}

// max |x - x_dense| / max |x_dense| for a random right-hand side.
double solve_error(const CyclicBlockBand& band, const Eigen::MatrixXd& A, unsigned seed) {
  std::mt19937_64 gen(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::VectorXd rhs(A.rows());
  for (Eigen::Index k = 0; k < rhs.size(); ++k) rhs(k) = g(gen);
  const Eigen::VectorXd truth = A.llt().solve(rhs);
  Eigen::VectorXd x = rhs;
  band.solve(x.data());
  return (x - truth).cwiseAbs().maxCoeff() / truth.cwiseAbs().maxCoeff();
}

}  // namespace

TEST(NumericsBlockBand, SolvesLikeADenseCholesky) {
  for (std::size_t N : {9u, 10u, 17u, 64u}) {
    CyclicBlockBand band(N, 4);
    const Eigen::MatrixXd A = random_band(band, 7u + static_cast<unsigned>(N), 0.5);
    ASSERT_TRUE(band.factorise()) << "N = " << N;
    EXPECT_LT(solve_error(band, A, 3u), 1e-10) << "N = " << N;
  }
}

TEST(NumericsBlockBand, SolvesTheKilobaseRingSize) {
  CyclicBlockBand band(1050, 4);
  const Eigen::MatrixXd A = random_band(band, 11u, 0.5);
  ASSERT_TRUE(band.factorise());
  EXPECT_LT(solve_error(band, A, 5u), 1e-10);
  // a well-conditioned band: its fill decays and most of it is dropped, to round-off
  EXPECT_LT(band.fill_columns(), 1050u / 2);
}

TEST(NumericsBlockBand, KeepsAFillThatDoesNotDecay) {
  // A ring Laplacian with shift 1e-6: the fill decays over ~1000 blocks, none of the 196
  // columns may be dropped, and the solve matches the dense one (condition number ~1e6).
  CyclicBlockBand band(200, 4);
  const Eigen::MatrixXd A = random_band(band, 13u, 1e-6, true, /*laplacian=*/true);
  ASSERT_TRUE(band.factorise());
  EXPECT_EQ(band.fill_columns(), 200u - 4u);
  EXPECT_LT(solve_error(band, A, 9u), 1e-8);
}

TEST(NumericsBlockBand, DroppingTheCornersIsWrong) {
  // control: the same ring without the blocks that close it (an open band)
  CyclicBlockBand band(64, 4);
  const Eigen::MatrixXd A = random_band(band, 71u, 0.5, /*corners=*/false);
  ASSERT_TRUE(band.factorise());
  EXPECT_GT(solve_error(band, A, 3u), 1e-3);
}

TEST(NumericsBlockBand, RefusesWhatItCannotHold) {
  // N <= 2 b: blocks would couple both ways round; b = 0 is no band
  EXPECT_THROW(CyclicBlockBand(8, 4), rodcore::InputError);
  EXPECT_THROW(CyclicBlockBand(10, 0), rodcore::InputError);
  // not positive definite: factorise says so, and solve() refuses
  CyclicBlockBand band(12, 4);
  random_band(band, 3u, 0.5);
  band.lower(5, 0) = -band.lower(5, 0);
  EXPECT_FALSE(band.factorise());
  std::vector<double> x(6 * 12, 1.0);
  EXPECT_THROW(band.solve(x.data()), rodcore::NumericalError);
}
