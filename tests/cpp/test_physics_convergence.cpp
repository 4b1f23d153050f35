// Convergence of the full solver on the exact twisted wave: FD4 in space
// with order 4, RK4 in time with order 4, the spectral operator
// exponentially in N; and the asymptotic untwisted wave (Eqs 40-45 as
// corrected in docs/numerics.md) satisfies Eqs 11-14 up to O(eps^3).
#include <gtest/gtest.h>

#include <cmath>

#include "physics_test_util.hpp"
#include "rodcore/analytic.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/rhs.hpp"

using namespace rodcore;
using namespace rodtest;

namespace {
// max error of all 12 fields at t_end against the exact wave
double wave_error(Scene sc, double t_end) {
  analytic::TwistedWave w;
  w.A = sc.initial.numbers.at("A");
  w.k = 2 * kPi / sc.rod.length;
  w.kappa_branch = sc.initial.strings.at("kappa");
  w.omega_branch = sc.initial.strings.at("branch") == "plus" ? 1 : -1;
  w.D1 = sc.material.D[0];
  sc.output.t_end = t_end;
  sc.output.frames = 2;
  const auto r = run_scene(sc);
  const int N = sc.rod.points;
  double e = 0.0;
  for (int i = 0; i < N; ++i) {
    const auto f = w.at(i * sc.rod.length / N, t_end);
    for (int c = 0; c < 12; ++c) e = std::max(e, std::abs(r.y.back()[c * N + i] - f[c]));
  }
  return e;
}
}  // namespace

TEST(PhysicsConvergence, FD4InSpaceIsFourthOrder) {
  double prev = 0.0;
  std::vector<double> orders;
  for (int N : {16, 32, 64}) {
    Scene sc = twisted_wave_scene(N, "p", "plus", 0.5);
    sc.solver.space = SpaceMethod::fd4;
    sc.solver.rtol = sc.solver.atol = 1e-13;
    const double e = wave_error(sc, 1.0);
    if (prev > 0) orders.push_back(std::log2(prev / e));
    prev = e;
  }
  for (double p : orders) EXPECT_NEAR(p, 4.0, 0.2);
}

TEST(PhysicsConvergence, RK4InTimeIsFourthOrder) {
  std::vector<double> e;
  for (double dt : {0.02, 0.01, 0.005}) {
    Scene sc = twisted_wave_scene(16, "m", "plus", 0.5);
    sc.solver.time = TimeMethod::rk4;
    sc.solver.dt = dt;
    e.push_back(wave_error(sc, 2.0));
  }
  EXPECT_NEAR(e[0] / e[1], 16.0, 1.5);
  EXPECT_NEAR(e[1] / e[2], 16.0, 1.0);
}

TEST(PhysicsConvergence, SpectralErrorFallsExponentially) {
  // the untwisted wave of finite amplitude excites all harmonics; compare
  // N = 8 .. 24 against N = 48 at common grid points
  auto run = [](int N) {
    Scene sc;
    sc.source = "<test>";
    sc.rod.length = 2 * kPi;
    sc.rod.points = N;
    sc.initial.kind = InitialKind::untwisted_wave;
    sc.initial.numbers = {{"mode", 1.0}, {"epsilon", 0.3}};
    sc.initial.strings = {{"branch", "plus"}};
    sc.solver.rtol = sc.solver.atol = 1e-13;
    sc.output.t_end = 3.0;
    return run_scene(sc).y.back();
  };
  const auto ref = run(48);
  std::vector<double> errs;
  for (int N : {8, 12, 16, 24}) {
    const auto y = run(N);
    double e = 0.0;
    for (int c = 0; c < 12; ++c)
      for (int i = 0; i < N; ++i) e = std::max(e, std::abs(y[c * N + i] - ref[c * 48 + i * (48 / N)]));
    errs.push_back(e);
  }
  for (std::size_t j = 1; j < errs.size(); ++j)
    EXPECT_LT(errs[j], errs[j - 1] / 8.0) << "N step " << j;  // geometric, > (N ratio)^4
  EXPECT_LT(errs.back(), 1e-8);
}

TEST(PhysicsConvergence, UntwistedWaveResidualIsThirdOrderInEps) {
  // d/dt of the asymptotic fields (central difference in t, h = 1e-4) minus
  // the RHS must scale as eps^3: halving eps divides it by ~8. With the
  // paper's printed signs (Eqs 42-43) or k^2 C3^2 (Eqs 44-45) it would not.
  auto residual = [](double eps, int branch) {
    analytic::UntwistedWave w;
    w.eps = eps;
    w.k = 1.0;
    w.omega_branch = branch;
    const int N = 32;
    Rod rod;
    rod.length = 2 * kPi;
    rod.points = N;
    Material m;
    auto op = make_derivative_operator(SpaceMethod::spectral, N, rod.length);
    RodRHS rhs(rod, m, *op);
    w.D1 = m.D[0];
    w.C3 = m.C[2];
    std::vector<double> y(12 * N), f(12 * N);
    for (int i = 0; i < N; ++i) {
      const auto a = w.at(i * rod.length / N, 0.0);
      for (int c = 0; c < 12; ++c) y[c * N + i] = a[c];
    }
    rhs(y.data(), f.data());
    const double h = 1e-4;
    double r = 0.0;
    for (int i = 0; i < N; ++i) {
      const double s = i * rod.length / N;
      const auto p = w.at(s, h), q = w.at(s, -h), p2 = w.at(s, 2 * h), q2 = w.at(s, -2 * h);
      for (int c = 0; c < 12; ++c) {
        const double dt = (8 * (p[c] - q[c]) - (p2[c] - q2[c])) / (12 * h);
        r = std::max(r, std::abs(dt - f[c * N + i]));
      }
    }
    return r;
  };
  for (int b : {+1, -1}) {
    const double r1 = residual(0.02, b), r2 = residual(0.01, b);
    EXPECT_NEAR(std::log2(r1 / r2), 3.0, 0.3) << "branch " << b << ": " << r1 << " " << r2;
  }
}
