// Spatial derivative operators against exact derivatives of smooth periodic
// functions: FD4 converges with order 4, the spectral operator exponentially
// (exact for resolved trigonometric polynomials); both are skew-symmetric.
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <vector>

#include "physics_test_util.hpp"
#include "rodcore/error.hpp"
#include "rodcore/operators.hpp"

using namespace rodcore;
using rodtest::kPi;

namespace {
// f = exp(sin s) on L = 2 pi, f' = cos(s) exp(sin s)
double deriv_error(const std::string& kind, int N) {
  const double L = 2.0 * kPi;
  auto op = make_derivative_operator(*from_string<SpaceMethod>(kind), N, L);
  std::vector<double> f(N), df(N);
  for (int i = 0; i < N; ++i) f[i] = std::exp(std::sin(i * L / N));
  op->apply(f.data(), df.data(), 1);
  double e = 0.0;
  for (int i = 0; i < N; ++i) {
    const double s = i * L / N;
    e = std::max(e, std::abs(df[i] - std::cos(s) * std::exp(std::sin(s))));
  }
  return e;
}
}  // namespace

TEST(NumericsOperators, FD4ConvergesWithOrder4) {
  const double e1 = deriv_error("fd4", 32), e2 = deriv_error("fd4", 64), e3 = deriv_error("fd4", 128);
  const double p1 = std::log2(e1 / e2), p2 = std::log2(e2 / e3);
  EXPECT_NEAR(p1, 4.0, 0.25);
  EXPECT_NEAR(p2, 4.0, 0.1);
}

TEST(NumericsOperators, SpectralConvergesExponentially) {
  double prev = 1.0;
  for (int N : {8, 12, 16, 20, 24}) {
    const double e = deriv_error("spectral", N);
    EXPECT_LT(e, prev / 20.0) << "N = " << N;  // geometric decrease, not algebraic
    prev = e;
  }
  EXPECT_LT(deriv_error("spectral", 32), 1e-13);
}

TEST(NumericsOperators, SpectralExactForResolvedModesNyquistZeroDealias) {
  const int N = 24;
  const double L = 3.0;
  auto op = make_derivative_operator(SpaceMethod::spectral, N, L);
  auto opd = make_derivative_operator(SpaceMethod::spectral, N, L, true);
  std::vector<double> f(2 * N), df(2 * N), dfd(2 * N);
  for (int m : {1, 5, 8, 11, 12}) {
    const double k = 2 * kPi * m / L;
    for (int i = 0; i < N; ++i) {
      f[i] = std::sin(k * i * L / N + 0.3);
      f[N + i] = std::cos(k * i * L / N);
    }
    op->apply(f.data(), df.data(), 2);
    opd->apply(f.data(), dfd.data(), 2);
    for (int i = 0; i < N; ++i) {
      const double s = i * L / N;
      if (m < N / 2) {
        EXPECT_NEAR(df[i], k * std::cos(k * s + 0.3), 1e-12 * k);
        EXPECT_NEAR(df[N + i], -k * std::sin(k * s), 1e-12 * k);
      } else {  // Nyquist: cos(N/2 s) on the grid has zero derivative
        EXPECT_NEAR(df[N + i], 0.0, 1e-12 * k);
      }
      if (3 * m > N) {  // 2/3 rule: the derivative of a cut mode is zero
        EXPECT_NEAR(dfd[i], 0.0, 1e-12 * k);
      } else {
        EXPECT_NEAR(dfd[i], k * std::cos(k * s + 0.3), 1e-12 * k);
      }
    }
  }
  EXPECT_NEAR(opd->max_wavenumber(), 2 * kPi * 8 / L, 1e-12);
  EXPECT_NEAR(op->max_wavenumber(), 2 * kPi * 11 / L, 1e-12);
}

TEST(NumericsOperators, SkewSymmetric) {
  // <u, D v> = -<D u, v>: the reason the semi-discrete energy is conserved.
  std::mt19937 gen(7);
  std::normal_distribution<double> nd;
  for (const char* kind : {"fd4", "spectral"}) {
    for (bool dealias : {false, true}) {
      const int N = 30;
      auto op = make_derivative_operator(*from_string<SpaceMethod>(kind), N, 2.5, dealias);
      std::vector<double> u(N), v(N), du(N), dv(N);
      for (int i = 0; i < N; ++i) {
        u[i] = nd(gen);
        v[i] = nd(gen);
      }
      op->apply(u.data(), du.data(), 1);
      op->apply(v.data(), dv.data(), 1);
      double a = 0, b = 0, n = 0;
      for (int i = 0; i < N; ++i) {
        a += u[i] * dv[i];
        b += du[i] * v[i];
        n += std::abs(u[i] * dv[i]);
      }
      EXPECT_NEAR(a, -b, 1e-13 * n) << kind;
    }
  }
}

TEST(NumericsOperators, FD4MaxWavenumberIsTheSymbolMaximum) {
  const int N = 2000;
  const double L = 1.0, h = L / N;
  auto op = make_derivative_operator(SpaceMethod::fd4, N, L);
  double m = 0.0;
  for (int j = 0; j <= N / 2; ++j) {
    const double th = 2 * kPi * j / N;
    m = std::max(m, (8 * std::sin(th) - std::sin(2 * th)) / (6 * h));
  }
  EXPECT_NEAR(op->max_wavenumber(), m, 1e-6 * m);
  EXPECT_NEAR(op->max_wavenumber() * h, 1.3722, 1e-4);
}

TEST(NumericsOperators, BadKindOrSize) {
  EXPECT_THROW(make_derivative_operator(SpaceMethod::automatic, 16, 1.0), InputError);
  EXPECT_THROW(make_derivative_operator(static_cast<SpaceMethod>(99), 16, 1.0), InputError);
  EXPECT_THROW(make_derivative_operator(SpaceMethod::fd4, 4, 1.0), InputError);
  EXPECT_THROW(make_derivative_operator(SpaceMethod::spectral, 16, -1.0), InputError);
}
