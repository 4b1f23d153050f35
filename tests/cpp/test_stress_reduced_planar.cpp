// The reduced planar system (reduced_planar.hpp) against the full system.
// Independent truths: the planar set {gamma1, gamma3, omega2, Gamma1, Gamma3,
// Omega2} of an untwisted straight rod is invariant under Eqs 11-14 (every
// term feeding another row is a product with one of the zero rows), so the
// FULL system started in it keeps the other six rows exactly (bitwise) zero;
// and a fixed-step integrator then does the same arithmetic on the kept rows
// whether or not the zero rows are carried along.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <vector>

#include "rodcore/analytic.hpp"
#include "rodcore/error.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/reduced_planar.hpp"
#include "rodcore/rhs.hpp"

namespace {

using namespace rodcore;

struct Problem {
  Rod rod;
  Material mat;
  std::unique_ptr<DerivativeOperator> op;
  std::unique_ptr<RodRHS> rhs;
  std::vector<double> y0;

  // The paper's Sec 5.2 wave: k = 2, eps = 0.5, Gamma03 = 1 (large amplitude).
  Problem(const char* space, std::size_t N) {
    rod.length = 2.0 * std::numbers::pi;
    rod.points = static_cast<int>(N);
    rod.Gamma0 = {0.0, 0.0, 1.0};
    rod.Omega0 = {0.0, 0.0, 0.0};
    op = make_derivative_operator(*from_string<SpaceMethod>(space), N, rod.length);
    rhs = std::make_unique<RodRHS>(rod, mat, *op);
    analytic::UntwistedWave w;
    w.eps = 0.5;
    w.k = 2.0;
    y0.assign(12 * N, 0.0);
    for (std::size_t i = 0; i < N; ++i) {
      const auto v = w.at(rod.length * static_cast<double>(i) / static_cast<double>(N), 0.0);
      for (int r = 0; r < 12; ++r) y0[r * N + i] = v[r];
    }
  }
};

std::vector<double> integrate(const std::string& kind, std::size_t n,
                              std::function<void(const double*, double*)> f, const std::vector<double>& y0,
                              double t_end, double tol, double dt) {
  OdeSystem sys;
  sys.n = n;
  sys.f = [f](double, const double* y, double* d) { f(y, d); };
  IntegratorOptions io;
  io.rtol = io.atol = tol;
  io.dt = dt;
  auto integ = make_time_integrator(*from_string<TimeMethod>(kind), sys, io);
  integ->reset(0.0, y0.data());
  while (integ->t() < t_end) integ->step(t_end);
  return integ->y();
}

TEST(ReducedPlanar, AllowedOnlyForUntwistedStraightUniformRod) {
  Rod rod;
  rod.Gamma0 = {0.0, 0.0, 1.2};
  rod.Omega0 = {0.0, 0.0, 0.0};
  EXPECT_TRUE(planar_reduction_allowed(rod));
  rod.Omega0 = {0.0, 0.0, 0.5};  // twisted: the twisted wave leaves the set
  EXPECT_FALSE(planar_reduction_allowed(rod));
  rod.Omega0 = {0.0, 0.0, 0.0};
  rod.Gamma0 = {0.1, 0.0, 1.0};
  EXPECT_FALSE(planar_reduction_allowed(rod));
}

TEST(ReducedPlanar, InitialWaveIsInTheSubspaceAndNoiseIsNot) {
  Problem p("spectral", 32);
  EXPECT_TRUE(in_planar_subspace(p.y0.data(), 32));
  p.y0[row(Omega, 2) * 32 + 5] = 1e-300;
  EXPECT_FALSE(in_planar_subspace(p.y0.data(), 32));
}

class ReducedPlanarOps : public ::testing::TestWithParam<const char*> {};

TEST_P(ReducedPlanarOps, FullSystemKeepsTheZeroRowsExactlyZero) {
  const std::size_t N = 64;
  Problem p(GetParam(), N);
  const auto y = integrate(
      "dop853", 12 * N, [&](const double* a, double* b) { (*p.rhs)(a, b); }, p.y0, 5.0, 1e-10, 0.01);
  EXPECT_TRUE(in_planar_subspace(y.data(), N));
  // ... and the state has moved far from the start (the test means something).
  double moved = 0.0;
  for (std::size_t j = 0; j < y.size(); ++j) moved = std::max(moved, std::abs(y[j] - p.y0[j]));
  EXPECT_GT(moved, 0.1);
}

TEST_P(ReducedPlanarOps, ReducedEqualsFullWithFixedSteps) {
  const std::size_t N = 64;
  Problem p(GetParam(), N);
  const double dt = 0.01, t_end = 5.0;  // rk4: fixed dt, tolerances unused
  const auto full = integrate(
      "rk4", 12 * N, [&](const double* a, double* b) { (*p.rhs)(a, b); }, p.y0, t_end, 1e-10, dt);
  std::vector<double> y6(6 * N), back(12 * N);
  double diff = 0.0;
  {
    PlanarRHS planar(*p.rhs);
    planar.reduce(p.y0.data(), y6.data());
    const auto red = integrate(
        "rk4", 6 * N, [&](const double* a, double* b) { planar(a, b); }, y6, t_end, 1e-10, dt);
    planar.expand(red.data(), back.data());
  }
  for (std::size_t j = 0; j < back.size(); ++j) diff = std::max(diff, std::abs(back[j] - full[j]));
  EXPECT_LE(diff, 1e-12);
  // The full RHS is itself again after the reduced system is gone.
  std::vector<double> f1(12 * N), f2(12 * N);
  auto noisy = p.y0;
  for (std::size_t i = 0; i < N; ++i) noisy[row(Omega, 2) * N + i] = 0.01 * std::sin(3.0 * i);
  (*p.rhs)(noisy.data(), f1.data());
  Problem fresh(GetParam(), N);
  (*fresh.rhs)(noisy.data(), f2.data());
  for (std::size_t j = 0; j < f1.size(); ++j) ASSERT_EQ(f1[j], f2[j]) << j;
}

TEST_P(ReducedPlanarOps, ReducedEqualsFullAdaptiveToTolerance) {
  // The adaptive error norm is an RMS over the state, so the zero rows change
  // the step sequence: agreement is at the tolerance, not at round-off.
  const std::size_t N = 64;
  Problem p(GetParam(), N);
  const auto full = integrate(
      "dop853", 12 * N, [&](const double* a, double* b) { (*p.rhs)(a, b); }, p.y0, 10.0, 1e-12, 0.01);
  PlanarRHS planar(*p.rhs);
  std::vector<double> y6(6 * N), back(12 * N);
  planar.reduce(p.y0.data(), y6.data());
  const auto red = integrate(
      "dop853", 6 * N, [&](const double* a, double* b) { planar(a, b); }, y6, 10.0, 1e-12, 0.01);
  planar.expand(red.data(), back.data());
  double diff = 0.0;
  for (std::size_t j = 0; j < back.size(); ++j) diff = std::max(diff, std::abs(back[j] - full[j]));
  EXPECT_LE(diff, 1e-9);
}

INSTANTIATE_TEST_SUITE_P(Operators, ReducedPlanarOps, ::testing::Values("fd4", "spectral"));

TEST(ReducedPlanar, BadRowIsAnError) {
  Problem p("fd4", 16);
  EXPECT_THROW(p.rhs->set_nonzero_rows({0, 12}), InputError);
}

}  // namespace
