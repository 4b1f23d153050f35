// Pure shear oscillation of a TWISTED rod (paper Sec 3.1.1, Fig 4): the
// s-independent motion of Eqs 28-30 seen through the twist. Independent
// truths: (1) no bend, Omega stays (0, 0, Omega03) to round-off, and gamma
// stays 0; (2) rotated back by th = Omega03 s into the untwisted frame, the
// fields are s-independent and follow Eqs 28-30, integrated here by a
// separate classic RK4 with a tiny step; (3) the kind refuses the cases where
// this is not a solution (anisotropic cross-section, non-periodic twist).
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "physics_test_util.hpp"
#include "rodcore/error.hpp"

namespace {

using namespace rodcore;
using rodtest::kPi;

Scene twisted_shear_scene() {
  Scene sc;
  sc.source = "<test>";
  sc.rod.length = 2.0 * kPi;
  sc.rod.points = 32;
  sc.rod.Gamma0 = {0.0, 0.0, 1.0};
  sc.rod.Omega0 = {0.0, 0.0, 2.0};  // two turns over the rod
  sc.initial.kind = InitialKind::shear_oscillation;
  sc.initial.numbers = {{"omega2", 0.4}, {"Gamma1", 0.5}, {"Gamma3", 1.1}};
  sc.solver.rtol = sc.solver.atol = 1e-12;
  sc.output.t_end = 3.0;
  sc.output.frames = 7;
  return sc;
}

TEST(ShearOscillationTwisted, NoBendAndEqs28to30InTheUntwistedFrame) {
  const Scene sc = twisted_shear_scene();
  const double C1 = sc.material.C[0], C3 = sc.material.C[2], I2 = sc.material.I[1], G03 = 1.0;
  auto f = [&](const std::array<double, 3>& u) {  // (omega2, Gamma1, Gamma3), Eqs 28-30
    return std::array<double, 3>{(C1 * u[1] * u[2] - C3 * u[1] * (u[2] - G03)) / I2, -u[0] * u[2],
                                 u[0] * u[1]};
  };
  const auto r = rodtest::run_scene(sc);
  ASSERT_EQ(r.y.size(), 7u);
  std::array<double, 3> u{0.4, 0.5, 1.1};
  const int per_frame = 5000;
  const double h = 0.5 / per_frame;
  const std::size_t N = 32;
  for (std::size_t j = 0; j < r.y.size(); ++j) {
    if (j > 0)
      for (int k = 0; k < per_frame; ++k) {
        auto add = [](const std::array<double, 3>& a, const std::array<double, 3>& b, double c) {
          return std::array<double, 3>{a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2]};
        };
        const auto k1 = f(u), k2 = f(add(u, k1, h / 2)), k3 = f(add(u, k2, h / 2)), k4 = f(add(u, k3, h));
        for (int c = 0; c < 3; ++c) u[c] += h / 6 * (k1[c] + 2 * k2[c] + 2 * k3[c] + k4[c]);
      }
    const auto& y = r.y[j];
    for (std::size_t i = 0; i < N; ++i) {
      const double th = 2.0 * (2.0 * kPi * static_cast<double>(i) / N);
      const double c = std::cos(th), s = std::sin(th);
      // no bend, no translation
      EXPECT_NEAR(y[9 * N + i], 0.0, 1e-12);
      EXPECT_NEAR(y[10 * N + i], 0.0, 1e-12);
      EXPECT_NEAR(y[11 * N + i], 2.0, 1e-12);
      for (int k = 0; k < 3; ++k) EXPECT_NEAR(y[k * N + i], 0.0, 1e-12);
      // untwisted-frame components: v_untw = R_Z(th) v_body
      const double w1u = c * y[3 * N + i] - s * y[4 * N + i], w2u = s * y[3 * N + i] + c * y[4 * N + i];
      const double G1u = c * y[6 * N + i] - s * y[7 * N + i], G2u = s * y[6 * N + i] + c * y[7 * N + i];
      EXPECT_NEAR(w1u, 0.0, 1e-12);
      EXPECT_NEAR(G2u, 0.0, 1e-12);
      EXPECT_NEAR(y[5 * N + i], 0.0, 1e-12);
      EXPECT_NEAR(w2u, u[0], 1e-9) << "frame " << j << " point " << i;
      EXPECT_NEAR(G1u, u[1], 1e-9) << "frame " << j << " point " << i;
      EXPECT_NEAR(y[8 * N + i], u[2], 1e-9) << "frame " << j << " point " << i;
    }
  }
  EXPECT_GT(std::abs(u[1] - 0.5), 0.05);  // the shear really moved
}

TEST(ShearOscillationTwisted, RefusedWhereItIsNotASolution) {
  Scene sc = twisted_shear_scene();
  sc.material.C = {1.0, 1.2, 1.19};
  EXPECT_THROW(Simulation{sc}, InputError);
  sc = twisted_shear_scene();
  sc.rod.Omega0 = {0.0, 0.0, 1.5};  // 1.5 turns: the fields would not be periodic
  EXPECT_THROW(Simulation{sc}, InputError);
  sc = twisted_shear_scene();
  sc.rod.Gamma0 = {0.1, 0.0, 1.0};
  EXPECT_THROW(Simulation{sc}, InputError);
}

}  // namespace
