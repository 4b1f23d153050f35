// The exact twisted-rod wave (paper Eq 24, checked form in docs/numerics.md)
// is an exact solution of the full nonlinear Eqs 11-14: it must satisfy the
// discrete RHS to round-off and be reproduced by the solver after one period.
#include <gtest/gtest.h>

#include "physics_test_util.hpp"
#include "rodcore/analytic.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/rhs.hpp"

using namespace rodcore;
using namespace rodtest;

namespace {

analytic::TwistedWave wave_of(const Scene& sc) {
  analytic::TwistedWave w;
  w.A = sc.initial.numbers.at("A");
  w.k = 2.0 * kPi * sc.initial.numbers.at("mode") / sc.rod.length;
  w.Gamma03 = sc.rod.Gamma0[2];
  w.Omega03 = sc.rod.Omega0[2];
  w.D1 = sc.material.D[0];
  w.kappa_branch = sc.initial.strings.at("kappa");
  w.omega_branch = sc.initial.strings.at("branch") == "plus" ? 1 : -1;
  return w;
}

struct Branch {
  const char* kappa;
  const char* branch;
};

class TwistedWave : public ::testing::TestWithParam<Branch> {};

}  // namespace

TEST(PhysicsTwistedWave, DispersionSolvesEq25) {
  // Eq 26 must be a root of the quartic Eq 25 on all four branches.
  const double D1 = 1.21, G03 = 1.0;
  for (double kappa : {-3.0, -0.5, 0.1, 1.0, 3.0, 10.0}) {
    for (int b : {+1, -1}) {
      const double w = analytic::dispersion(kappa, D1, G03, b);
      const double lhs = (w * w - kappa * kappa * D1) * (w * w - kappa * kappa);
      EXPECT_NEAR(lhs, w * w * G03 * G03, 1e-12 * std::max(1.0, w * w * w * w)) << kappa << " " << b;
    }
  }
  // limits quoted in the text: w_- ~ kappa^2 sqrt(D1) / G03 for small kappa,
  // w_+ -> G03 + kappa^2 (D1 + 1) / (2 G03)
  const double kap = 1e-3;
  EXPECT_NEAR(analytic::dispersion(kap, D1, G03, -1), kap * kap * std::sqrt(D1) / G03, 1e-10);
  EXPECT_NEAR(analytic::dispersion(kap, D1, G03, +1), G03 + kap * kap * (D1 + 1) / (2 * G03), 1e-10);
}

TEST(PhysicsTwistedWave, EnergyRatioEq27MatchesFields) {
  // Eq 27 from the exact fields: Gamma_perp^2 / (D1 Omega_perp^2).
  for (const char* kb : {"p", "m"}) {
    for (int b : {1, -1}) {
      analytic::TwistedWave w;
      w.kappa_branch = kb;
      w.omega_branch = b;
      const auto f = w.at(0.3, 0.7);
      const double G2 = f[6] * f[6] + f[7] * f[7], O2 = f[9] * f[9] + f[10] * f[10];
      EXPECT_NEAR(G2 / (w.D1 * O2), analytic::energy_ratio(w.w(), w.kappa(), w.D1, w.Gamma03),
                  1e-12 * (1 + G2 / (w.D1 * O2)));
    }
  }
}

TEST_P(TwistedWave, SatisfiesRhsToRoundOff) {
  const Branch br = GetParam();
  for (const char* space : {"spectral", "fd4"}) {
    Scene sc = twisted_wave_scene(32, br.kappa, br.branch, 0.5);
    sc.material.D = {1.21, 1.21, 2.0};  // D3, C3, I3 are free in the exact solution
    sc.material.C = {1.0, 1.0, 1.7};
    sc.material.I = {1.0, 1.0, 3.0};
    auto op = make_derivative_operator(*from_string<SpaceMethod>(space), 32, sc.rod.length);
    RodRHS rhs(sc.rod, sc.material, *op);
    const auto y = make_initial_state(sc);
    std::vector<double> f(y.size());
    rhs(y.data(), f.data());
    const auto w = wave_of(sc);
    double err = 0.0, scale = 0.0;
    for (int i = 0; i < 32; ++i) {
      const auto dt = w.d_dt(i * sc.rod.length / 32, 0.0);
      for (int r = 0; r < 12; ++r) {
        err = std::max(err, std::abs(f[r * 32 + i] - dt[r]));
        scale = std::max(scale, std::abs(dt[r]));
      }
    }
    if (std::string(space) == "spectral") {
      EXPECT_LT(err, 1e-13 * std::max(1.0, scale)) << "spectral residual";
    } else {
      // FD4 differentiates a sinusoid of wavenumber k with error ~ k (kh)^4 / 30
      double amp = 0.0;
      for (double v : y) amp = std::max(amp, std::abs(v));
      const double kh = w.k * sc.rod.length / 32;
      EXPECT_LT(err, 1.5 * w.k * std::pow(kh, 4) / 30.0 * amp) << "fd4 residual";
      EXPECT_GT(err, 1e-8) << "fd4 is not exact: the check must be able to fail";
    }
  }
}

TEST_P(TwistedWave, OnePeriodSpectralDop853Within1e9) {
  const Branch br = GetParam();
  Scene sc = twisted_wave_scene(16, br.kappa, br.branch, 0.5);
  const auto w = wave_of(sc);
  sc.solver.space = SpaceMethod::spectral;
  sc.solver.time = TimeMethod::dop853;
  sc.solver.rtol = 1e-12;
  sc.solver.atol = 1e-12;
  sc.output.t_end = w.period();
  sc.output.frames = 5;
  sc.output.energy = true;
  const auto r = run_scene(sc);
  ASSERT_EQ(r.y.size(), 5u);
  for (std::size_t f = 0; f < r.y.size(); ++f) {
    std::vector<double> exact(12 * 16);
    for (int i = 0; i < 16; ++i) {
      const auto e = w.at(i * sc.rod.length / 16, r.t[f]);
      for (int c = 0; c < 12; ++c) exact[c * 16 + i] = e[c];
    }
    EXPECT_LT(max_abs_diff(r.y[f], exact), 1e-9) << "frame " << f << " t = " << r.t[f];
  }
  EXPECT_NEAR(r.t.back(), w.period(), 1e-15);
  EXPECT_LT(r.summary.energy_drift, 1e-10);
}

INSTANTIATE_TEST_SUITE_P(AllBranches, TwistedWave,
                         ::testing::Values(Branch{"p", "plus"}, Branch{"p", "minus"}, Branch{"m", "plus"},
                                           Branch{"m", "minus"}),
                         [](const auto& info) {
                           return std::string(info.param.kappa) + "_" + info.param.branch;
                         });
