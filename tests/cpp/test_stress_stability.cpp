// linear_spectral_radius (stability.hpp) against independent truths:
// (1) an untwisted, unsheared rod at rest decouples into 1-D wave equations and
//     the bend-shear pairs of Eq 39, whose largest frequency at wavenumber k is
//     w+(k) (analytic::dispersion, kappa = k); extension k sqrt(C3) and twist
//     k sqrt(D3/I3) are the others. The max over 0..kmax is their max at kmax.
// (2) fixed-step RK4 (|R(i x)| <= 1 iff x <= 2 sqrt 2) is stable just below
//     2 sqrt 2 / radius and unstable just above, on the twisted DNA rod where
//     the wave-speed estimate is far off.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <vector>

#include "rodcore/analytic.hpp"
#include "rodcore/error.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/stability.hpp"

namespace {

using namespace rodcore;

TEST(LinearSpectralRadius, UntwistedRodEqualsDispersionRelationAtKmax) {
  for (const char* space : {"fd4", "spectral"}) {
    Rod rod;
    rod.length = 2.0 * std::numbers::pi;
    rod.points = 32;
    rod.Gamma0 = {0.0, 0.0, 1.0};
    rod.Omega0 = {0.0, 0.0, 0.0};
    Material m;
    auto op = make_derivative_operator(*from_string<SpaceMethod>(space), 32, rod.length);
    RodRHS rhs(rod, m, *op);
    const double k = op->max_wavenumber();
    const double expected = std::max(
        {analytic::dispersion(k, m.D[0], 1.0, +1), k * std::sqrt(m.C[2]), k * std::sqrt(m.D[2] / m.I[2])});
    EXPECT_NEAR(linear_spectral_radius(rhs), expected, 1e-9 * expected) << space;
  }
}

double rk4_growth(const RodRHS& rhs, double dt, int steps) {
  const std::size_t N = rhs.N();
  std::vector<double> y(12 * N, 0.0);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < N; ++i) {
      y[(6 + c) * N + i] = rhs.Gamma0()[c * N];
      y[(9 + c) * N + i] = rhs.Omega0()[c * N];
    }
  const std::vector<double> rest = y;
  unsigned s = 12345;
  for (auto& v : y) {  // 1e-9 deterministic noise in every component
    s = s * 1103515245u + 12345u;
    v += 1e-9 * (static_cast<double>(s >> 8) / 16777216.0 - 0.5);
  }
  OdeSystem sys;
  sys.n = 12 * N;
  sys.f = [&](double, const double* a, double* b) { rhs(a, b); };
  IntegratorOptions io;
  io.dt = dt;
  auto integ = make_time_integrator(TimeMethod::rk4, sys, io);
  integ->reset(0.0, y.data());
  try {
    for (int n = 0; n < steps; ++n) integ->step(1e300);
  } catch (const NumericalError&) {
    return INFINITY;  // the integrator's own non-finite check: blown up
  }
  double d = 0.0;
  for (std::size_t j = 0; j < y.size(); ++j) {
    const double e = std::abs(integ->y()[j] - rest[j]);
    if (!std::isfinite(e)) return INFINITY;
    d = std::max(d, e);
  }
  return d / 5e-10;
}

TEST(LinearSpectralRadius, Rk4BoundaryOnTheDnaRod) {
  for (const char* space : {"fd4", "spectral"}) {
    Rod rod;
    rod.length = 158 * 3.38 / 5.0;
    rod.points = 64;
    rod.Gamma0 = {0.0, 0.0, 1.0};
    rod.Omega0 = {0.0, 0.0, 2.0 * std::numbers::pi * 15.0 / rod.length};
    Material m;
    auto op = make_derivative_operator(*from_string<SpaceMethod>(space), 64, rod.length);
    RodRHS rhs(rod, m, *op);
    const double dt_star = 2.0 * std::sqrt(2.0) / linear_spectral_radius(rhs);
    EXPECT_LT(rk4_growth(rhs, 0.97 * dt_star, 600), 100.0) << space;
    EXPECT_GT(rk4_growth(rhs, 1.03 * dt_star, 600), 1e6) << space;
  }
}

}  // namespace
