// Physical invariants and exact special solutions (paper Sec 3.1.1, 5.1,
// Appendix A): rest states stay at rest, rigid translations stay uniform,
// the balanced rotating ring keeps its radius, the spinning ring follows
// Eq 46, the pure shear oscillation follows Eqs 28-30 (integrated here by an
// independent RK4 with a tiny step) with the invariants of Eq 31, and the
// energy is conserved.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "physics_test_util.hpp"
#include "rodcore/analytic.hpp"
#include "rodcore/initial_conditions.hpp"

using namespace rodcore;
using namespace rodtest;

namespace {
Scene base_scene(int N, double L) {
  Scene sc;
  sc.source = "<test>";
  sc.rod.length = L;
  sc.rod.points = N;
  sc.solver.rtol = sc.solver.atol = 1e-12;
  sc.output.t_end = 5.0;
  sc.output.frames = 3;
  return sc;
}
}  // namespace

TEST(PhysicsInvariants, IntrinsicShapesAtRestStayAtRest) {
  const double L = 4.0;
  struct Shape {
    const char* name;
    Vec3 G0, O0;
  };
  const Shape shapes[] = {{"straight", {0, 0, 1}, {0, 0, 0}},
                          {"twisted", {0, 0, 1}, {0, 0, 1.3}},
                          {"ring", {0, 0, 1}, {2 * kPi / L, 0, 0}},
                          {"helix", {0.1, 0, 0.9}, {0.4, 0.2, 1.1}}};
  for (const auto& sh : shapes) {
    for (SpaceMethod space : {SpaceMethod::spectral, SpaceMethod::fd4}) {
      Scene sc = base_scene(24, L);
      sc.solver.space = space;
      sc.rod.Gamma0 = sh.G0;
      sc.rod.Omega0 = sh.O0;
      const auto r = run_scene(sc);
      EXPECT_LT(max_abs_diff(r.y.front(), r.y.back()), 1e-12) << sh.name << " " << to_string(space);
    }
  }
  // intrinsic shape varying along s
  Scene sc = base_scene(32, L);
  sc.rod.Gamma0_s.resize(3 * 32);
  sc.rod.Omega0_s.resize(3 * 32);
  for (int i = 0; i < 32; ++i) {
    const double s = i * L / 32;
    sc.rod.Gamma0_s[i] = 0.1 * std::sin(2 * kPi * s / L);
    sc.rod.Gamma0_s[32 + i] = 0.0;
    sc.rod.Gamma0_s[64 + i] = 1.0 + 0.05 * std::cos(4 * kPi * s / L);
    sc.rod.Omega0_s[i] = 0.3 * std::cos(2 * kPi * s / L);
    sc.rod.Omega0_s[32 + i] = 0.2;
    sc.rod.Omega0_s[64 + i] = 1.0 + 0.5 * std::sin(2 * kPi * s / L);
  }
  const auto r = run_scene(sc);
  EXPECT_LT(max_abs_diff(r.y.front(), r.y.back()), 1e-12) << "varying intrinsic shape";
}

TEST(PhysicsInvariants, UniformTranslationsStayUniform) {
  // A twisted rod (two full turns over L) translating rigidly in the lab:
  // gamma(s) = R(s)^T v is a single Fourier mode, steady in time; the
  // centerline moves by v t.
  const double L = 5.0;
  Scene sc = base_scene(16, L);
  sc.rod.Omega0 = {0.0, 0.0, 2 * 2 * kPi / L};
  sc.initial.numbers = {{"v1", 0.3}, {"v2", -0.2}, {"v3", 0.1}};
  sc.output.centerline = true;
  sc.output.t_end = 4.0;
  const auto r = run_scene(sc);
  EXPECT_LT(max_abs_diff(r.y.front(), r.y.back()), 1e-12);
  const double v[3] = {0.3, -0.2, 0.1};
  for (int i = 0; i < 16; ++i)
    for (int a = 0; a < 3; ++a) {
      EXPECT_NEAR(r.centerline.back()[3 * i + a] - r.centerline.front()[3 * i + a], v[a] * 4.0, 1e-12);
      // straight along d3 = e3 from the origin
      EXPECT_NEAR(r.centerline.front()[3 * i + a], a == 2 ? i * L / 16 : 0.0, 1e-12);
    }
}

TEST(PhysicsInvariants, BalancedRotatingRingKeepsItsRadius) {
  const double L = 2 * kPi;
  Scene sc = base_scene(32, L);
  sc.initial.kind = InitialKind::ring_rotating;
  sc.initial.numbers = {{"gamma3", 0.6}, {"balanced", 1.0}};
  sc.output.centerline = true;
  sc.output.t_end = 6.0;
  sc.output.frames = 4;
  const auto r = run_scene(sc);
  EXPECT_LT(max_abs_diff(r.y.front(), r.y.back()), 1e-12);
  // force balance: gamma3^2 / Gamma3 = C3 (Gamma3 - Gamma03)
  const double G3 = r.y[0][8 * 32], g3 = 0.6, C3 = sc.material.C[2];
  EXPECT_NEAR(g3 * g3 / G3, C3 * (G3 - 1.0), 1e-14);
  // geometry: a circle of radius R = Gamma3 L / 2 pi that turns rigidly at
  // rate omega1 = gamma3 Omega1 / Gamma3 about its fixed centre
  const double R = G3 * L / (2 * kPi), w1 = r.y[0][3 * 32];
  EXPECT_NEAR(w1, g3 * (2 * kPi / L) / G3, 1e-14);
  for (std::size_t f = 0; f < r.centerline.size(); ++f) {
    double c[3] = {0, 0, 0};
    for (int i = 0; i < 32; ++i)
      for (int a = 0; a < 3; ++a) c[a] += r.centerline[f][3 * i + a] / 32;
    for (int i = 0; i < 32; ++i) {
      double d2 = 0;
      for (int a = 0; a < 3; ++a) d2 += std::pow(r.centerline[f][3 * i + a] - c[a], 2);
      EXPECT_NEAR(std::sqrt(d2), R, 1e-10) << "frame " << f << " point " << i;
    }
    double chord = 0;
    for (int a = 0; a < 3; ++a) chord += std::pow(r.centerline[f][a] - r.centerline[0][a], 2);
    EXPECT_NEAR(std::sqrt(chord), 2 * R * std::abs(std::sin(0.5 * w1 * r.t[f])), 1e-9) << f;
  }
  // unbalanced: the ring breathes (the check above can fail)
  sc.initial.numbers["balanced"] = 0.0;
  sc.output.centerline = false;
  const auto u = run_scene(sc);
  EXPECT_GT(std::abs(u.y.back()[8 * 32] - u.y.front()[8 * 32]), 1e-3);
}

TEST(PhysicsInvariants, SpinningRingFollowsEq46) {
  const double L = 2 * kPi;
  Scene sc = base_scene(16, L);
  sc.initial.kind = InitialKind::ring_twisting;
  sc.initial.numbers = {{"omega3", 0.7}, {"A", 0.0}};
  sc.output.t_end = 5.0;
  sc.output.frames = 6;
  const auto r = run_scene(sc);
  const double A = 2 * kPi / L;
  for (std::size_t f = 0; f < r.y.size(); ++f)
    for (int i = 0; i < 16; ++i) {
      EXPECT_NEAR(r.y[f][9 * 16 + i], A * std::sin(0.7 * r.t[f]), 1e-10);
      EXPECT_NEAR(r.y[f][10 * 16 + i], A * std::cos(0.7 * r.t[f]), 1e-10);
      EXPECT_NEAR(r.y[f][5 * 16 + i], 0.7, 1e-12);
    }
}

TEST(PhysicsInvariants, ShearOscillationMatchesEqs28to30) {
  // Independent truth: Eqs 28-30 (with I2, C1, C3 as in Eq 12) integrated
  // here with classic RK4 and a tiny step.
  const double C1 = 1.0, C3 = 1.19, I2 = 1.0, G03 = 1.0;
  auto f = [&](const std::array<double, 3>& u) {  // (omega2, Gamma1, Gamma3)
    return std::array<double, 3>{(C1 * u[1] * u[2] - C3 * u[1] * (u[2] - G03)) / I2, -u[0] * u[2],
                                 u[0] * u[1]};
  };
  const double t_end = 3.0;
  std::array<double, 3> u{0.4, 0.5, 1.1};
  const int n = 30000;
  const double h = t_end / n;
  for (int k = 0; k < n; ++k) {
    auto add = [](const std::array<double, 3>& a, const std::array<double, 3>& b, double c) {
      return std::array<double, 3>{a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2]};
    };
    const auto k1 = f(u), k2 = f(add(u, k1, h / 2)), k3 = f(add(u, k2, h / 2)), k4 = f(add(u, k3, h));
    for (int j = 0; j < 3; ++j) u[j] += h / 6 * (k1[j] + 2 * k2[j] + 2 * k3[j] + k4[j]);
  }
  Scene sc = base_scene(8, 3.0);
  sc.initial.kind = InitialKind::shear_oscillation;
  sc.initial.numbers = {{"omega2", 0.4}, {"Gamma1", 0.5}, {"Gamma3", 1.1}};
  sc.output.t_end = t_end;
  sc.output.frames = 7;
  const auto r = run_scene(sc);
  const auto& yl = r.y.back();
  for (int i = 0; i < 8; ++i) {
    EXPECT_NEAR(yl[4 * 8 + i], u[0], 1e-9);
    EXPECT_NEAR(yl[6 * 8 + i], u[1], 1e-9);
    EXPECT_NEAR(yl[8 * 8 + i], u[2], 1e-9);
  }
  // Eq 31: Pi^2 = Gamma1^2 + Gamma3^2 and 2E = omega2^2 + C3 (Gamma3-G03)^2 + Gamma1^2
  const double Pi2 = 0.25 + 1.21, E2 = 0.16 + C3 * 0.01 + 0.25;
  for (const auto& y : r.y) {
    EXPECT_NEAR(y[6 * 8] * y[6 * 8] + y[8 * 8] * y[8 * 8], Pi2, 1e-10);
    EXPECT_NEAR(y[4 * 8] * y[4 * 8] + C3 * std::pow(y[8 * 8] - G03, 2) + y[6 * 8] * y[6 * 8], E2, 1e-10);
  }
}

TEST(PhysicsInvariants, EnergyConservedAndPartsExact) {
  // Nonlinear, multi-mode run (large-amplitude untwisted wave): energy
  // constant to 1e-10 relative with tight tolerances, both operators.
  for (SpaceMethod space : {SpaceMethod::spectral, SpaceMethod::fd4}) {
    Scene sc = base_scene(32, 2 * kPi);
    sc.solver.space = space;
    sc.initial.kind = InitialKind::untwisted_wave;
    sc.initial.numbers = {{"mode", 1.0}, {"epsilon", 0.4}};
    sc.initial.strings = {{"branch", "plus"}};
    sc.output.energy = true;
    sc.output.t_end = 10.0;
    sc.output.frames = 11;
    const auto r = run_scene(sc);
    ASSERT_EQ(r.energy.size(), 11u);
    for (double E : r.energy) EXPECT_NEAR(E / r.energy[0], 1.0, 1e-10) << to_string(space);
    // and the state did change a lot (the check is not vacuous)
    EXPECT_GT(max_abs_diff(r.y.front(), r.y[5]), 0.1);
  }
  // Parts of the exact twisted wave, pointwise constant: shear = L A^2 / 2,
  // kinetic_translational = L (kappa A / w)^2 / 2, extension = twist = 0.
  Scene sc = twisted_wave_scene(16, "p", "plus", 0.5);
  sc.output.energy_parts = true;
  Simulation sim(sc);
  std::map<std::string, double> parts;
  sim.add_observer(on_frame([&](const Frame& f) {
    if (f.index == 0) parts = f.energy_parts;
  }));
  sim.run();
  analytic::TwistedWave w;
  const double L = sc.rod.length;
  EXPECT_NEAR(parts.at("shear"), 0.5 * L * 0.25, 1e-14);
  EXPECT_NEAR(parts.at("kinetic_translational"), 0.5 * L * std::pow(w.kappa() * 0.5 / w.w(), 2), 1e-14);
  EXPECT_NEAR(parts.at("kinetic_rotational"), 0.5 * L * w.a_w() * w.a_w(), 1e-14);
  EXPECT_NEAR(parts.at("bend"), 0.5 * L * w.D1 * std::pow(w.kappa() * w.a_w() / w.w(), 2), 1e-14);
  EXPECT_EQ(parts.at("extension"), 0.0);
  EXPECT_EQ(parts.at("twist"), 0.0);
}
