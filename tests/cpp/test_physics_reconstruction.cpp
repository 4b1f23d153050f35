// Centerline and directors (paper Eqs 1-2) against exact shapes: a rigid
// helix (the frame is exp(s xi) in SE(3), computed here by Eigen's matrix
// exponential), and the DNA scene at t = 0, whose centerline is given in
// Sec 6.1: r(s,0) = (0, s, A cos(2 pi s/L)), d3 = (0, 1, 0); and the
// 4th order of the Magnus sweep on a non-uniform state.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <unsupported/Eigen/MatrixFunctions>

#include "physics_test_util.hpp"
#include "rodcore/dna_units.hpp"
#include "rodcore/reconstruction.hpp"

using namespace rodcore;
using namespace rodtest;

TEST(PhysicsReconstruction, RigidHelixIsExact) {
  const double L = 4.0;
  const int N = 16;
  const Vec3 G0{0.1, -0.05, 0.9}, O0{0.4, 0.2, 1.1};
  Scene sc;
  sc.source = "<test>";
  sc.rod.length = L;
  sc.rod.points = N;
  sc.rod.Gamma0 = G0;
  sc.rod.Omega0 = O0;
  sc.output.centerline = true;
  sc.output.directors = true;
  sc.output.t_end = 1.0;
  const auto r = run_scene(sc);
  Eigen::Matrix4d xi = Eigen::Matrix4d::Zero();
  xi.block<3, 3>(0, 0) << 0, -O0[2], O0[1], O0[2], 0, -O0[0], -O0[1], O0[0], 0;
  xi.block<3, 1>(0, 3) << G0[0], G0[1], G0[2];
  for (std::size_t f = 0; f < r.centerline.size(); ++f) {
    for (int i = 0; i < N; ++i) {
      const Eigen::Matrix4d g = (xi * (i * L / N)).exp();
      for (int a = 0; a < 3; ++a) {
        EXPECT_NEAR(r.centerline[f][3 * i + a], g(a, 3), 1e-12) << "point " << i;
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(r.directors[f][9 * i + 3 * a + k], g(a, k), 1e-12);
      }
    }
    EXPECT_LT(r.norm_error[f], 1e-13);
  }
}

TEST(PhysicsReconstruction, DnaPlanarCenterlineAtTimeZero) {
  // Checks the shape/sign derivation of Gamma from r(s,0) via Eq 47 and the
  // lab orientation (rod along Y, d1 || Z, d2 || X at s = 0), and the
  // accuracy of the sweep for a non-uniform Gamma.
  auto error = [](int N) {
    Scene sc;
    sc.source = "<test>";
    sc.initial.kind = InitialKind::dna_planar;
    sc.initial.numbers = {{"A_A", 10.0}};
    sc.rod.points = N;
    sc.output.centerline = true;
    sc.output.directors = true;
    sc.output.t_end = 0.0;
    sc.output.frames = 1;
    Simulation sim(sc);
    const double L = sim.scene().rod.length, O3 = sim.scene().rod.Omega0[2];
    EXPECT_NEAR(L, 158 * dna_units::rise_A / dna_units::ell_A, 1e-12);
    EXPECT_NEAR(O3 * L, 2 * kPi * 15, 1e-12);
    const double A = 10.0 / dna_units::ell_A;
    double e = 0.0, ed = 0.0, norm = 0.0;
    sim.add_observer(on_frame([&](const Frame& f) {
      norm = f.max_director_norm_error;
      for (std::size_t i = 0; i < f.N; ++i) {
        const double s = i * L / f.N;
        const double want[3] = {0.0, s, A * std::cos(2 * kPi * s / L)};
        for (int a = 0; a < 3; ++a) e = std::max(e, std::abs(f.centerline[3 * i + a] - want[a]));
        const double d1[3] = {std::sin(O3 * s), 0.0, std::cos(O3 * s)};
        const double d3[3] = {0.0, 1.0, 0.0};
        for (int a = 0; a < 3; ++a) {
          ed = std::max(ed, std::abs(f.directors[9 * i + 3 * a + 0] - d1[a]));
          ed = std::max(ed, std::abs(f.directors[9 * i + 3 * a + 2] - d3[a]));
        }
      }
    }));
    sim.run();
    EXPECT_LT(norm, 1e-13);
    return std::pair{e, ed};
  };
  const auto [e1, d1] = error(158);
  const auto [e2, d2] = error(316);
  EXPECT_LT(d1, 1e-12);  // the directors do not depend on Gamma: exact
  EXPECT_LT(d2, 1e-12);
  // The sweep substeps each grid interval to h |Omega| <= 0.05, so the
  // centerline error (~5e-8 l = 2.5e-7 A here) does not depend on N.
  const double A = 10.0 / dna_units::ell_A;
  EXPECT_LT(e1, 1e-7 * A);
  EXPECT_LT(e2, 1e-7 * A);
}

TEST(PhysicsReconstruction, QuaternionHelpers) {
  const double R[3][3] = {{0, 1, 0}, {0, 0, 1}, {1, 0, 0}};
  const Quat q = matrix_to_quat(R);
  double B[3][3];
  quat_to_matrix(q, B);
  for (int a = 0; a < 3; ++a)
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(B[a][k], R[a][k], 1e-15);
  // exp of a rotation by pi/2 about z maps x to y
  const Vec3 v = quat_rotate(quat_exp({0, 0, kPi / 2}), {1, 0, 0});
  EXPECT_NEAR(v[0], 0.0, 1e-15);
  EXPECT_NEAR(v[1], 1.0, 1e-15);
}

TEST(PhysicsReconstruction, MagnusSweepIsFourthOrder) {
  // Without substeps (|Omega| h small enough), a non-uniform state: the
  // closing frame of the exact twisted wave at t = 0 from N and 2N points
  // against 8N points converges with order 4.
  auto end_of = [](int N) {
    Scene sc = twisted_wave_scene(N, "p", "plus", 0.5);
    Simulation sim(sc);
    Reconstructor rec(N, sc.rod.length, std::numeric_limits<double>::infinity());
    return rec.sweep(sim.state().data(), Quat{1, 0, 0, 0}, Vec3{0, 0, 0}, nullptr, nullptr).r;
  };
  const Vec3 ref = end_of(1024);
  auto err = [&](int N) {
    const Vec3 r = end_of(N);
    return std::hypot(r[0] - ref[0], r[1] - ref[1], r[2] - ref[2]);
  };
  const double e1 = err(64), e2 = err(128);
  EXPECT_NEAR(std::log2(e1 / e2), 4.0, 0.4) << e1 << " " << e2;
}

TEST(PhysicsReconstruction, ClosureOfRingAndStraightRod) {
  // a balanced rotating ring closes (end_to_end = 0, no net rotation);
  // a straight rod with 2.25 turns of twist ends L further along d3 and
  // turned by 0.25 turn
  Scene sc;
  sc.source = "<test>";
  sc.rod.length = 2 * kPi;
  sc.rod.points = 32;
  sc.initial.kind = InitialKind::ring_rotating;
  sc.output.centerline = true;
  sc.output.t_end = 2.0;
  double gap = 1.0, rot = 1.0;
  Simulation ring(sc);
  ring.add_observer(on_frame([&](const Frame& f) {
    gap = std::hypot((*f.end_to_end)[0], (*f.end_to_end)[1], (*f.end_to_end)[2]);
    rot = *f.end_rotation;
  }));
  ring.run();
  EXPECT_LT(gap, 1e-12);
  EXPECT_LT(rot, 1e-12);
  Scene st;
  st.source = "<test>";
  st.rod.length = 3.0;
  st.rod.points = 16;
  st.rod.Omega0 = {0.0, 0.0, 2.25 * 2 * kPi / 3.0};
  st.output.directors = true;
  st.output.t_end = 0.0;
  st.output.frames = 1;
  Simulation straight(st);
  straight.add_observer(on_frame([&](const Frame& f) {
    EXPECT_NEAR((*f.end_to_end)[2], 3.0, 1e-12);
    EXPECT_NEAR(*f.end_rotation, 0.5 * kPi, 1e-12);
  }));
  straight.run();
}
