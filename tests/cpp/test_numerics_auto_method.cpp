// solver.space / solver.time = "auto" (the defaults): the rule of
// docs/performance.md. Independent truths: a smooth (analytic) initial state
// has no Fourier content above N/3 beyond round-off, a jump has O(1/k)
// coefficients (content ~N^-1/2), so the rule must give spectral for the
// first and fd4 for the second; a method given explicitly is kept.
#include <gtest/gtest.h>

#include "physics_test_util.hpp"

namespace {

using namespace rodcore;

TEST(AutoMethod, SmoothSceneGetsSpectralAndDop853) {
  Scene sc = rodtest::twisted_wave_scene(32, "p", "plus");
  ASSERT_EQ(sc.solver.space, SpaceMethod::automatic);
  ASSERT_EQ(sc.solver.time, TimeMethod::automatic);
  Simulation sim(sc);
  EXPECT_EQ(sim.scene().solver.space, SpaceMethod::spectral);
  EXPECT_EQ(sim.scene().solver.time, TimeMethod::dop853);
  EXPECT_EQ(sim.given_scene().solver.space, SpaceMethod::automatic);
  sc.output.t_end = 0.1;
  const auto r = rodtest::run_scene(sc);
  EXPECT_EQ(r.summary.method, "spectral+dop853");
  EXPECT_NE(r.summary.method_note.find("smooth"), std::string::npos) << r.summary.method_note;
}

TEST(AutoMethod, JumpInTheInitialFieldsGetsFd4) {
  // A rod at rest in an intrinsic shape with a jump in the twist: the state
  // (Omega = Omega0) is discontinuous.
  Scene sc;
  sc.source = "<test>";
  sc.rod.length = 2.0 * rodtest::kPi;
  sc.rod.points = 64;
  sc.rod.Gamma0_s.assign(3 * 64, 0.0);
  sc.rod.Omega0_s.assign(3 * 64, 0.0);
  for (int i = 0; i < 64; ++i) {
    sc.rod.Gamma0_s[2 * 64 + i] = 1.0;
    sc.rod.Omega0_s[2 * 64 + i] = i < 32 ? 0.5 : 1.0;
  }
  sc.initial.kind = InitialKind::rest;
  sc.output.t_end = 0.1;
  const auto r = rodtest::run_scene(sc);
  EXPECT_EQ(r.summary.method, "fd4+dop853");
  EXPECT_NE(r.summary.method_note.find("non-smooth"), std::string::npos) << r.summary.method_note;
  // The same rod with a smooth twist profile: spectral.
  for (int i = 0; i < 64; ++i)
    sc.rod.Omega0_s[2 * 64 + i] = 0.75 + 0.25 * std::sin(2.0 * rodtest::kPi * i / 64.0);
  EXPECT_EQ(rodtest::run_scene(sc).summary.method, "spectral+dop853");
}

TEST(AutoMethod, GivenMethodIsKept) {
  Scene sc = rodtest::twisted_wave_scene(32, "p", "plus");
  sc.solver.space = SpaceMethod::fd4;
  sc.solver.time = TimeMethod::rk4;
  sc.solver.dt = 1e-3;
  sc.output.t_end = 0.01;
  const auto r = rodtest::run_scene(sc);
  EXPECT_EQ(r.summary.method, "fd4+rk4");
  EXPECT_NE(r.summary.method_note.find("as given"), std::string::npos) << r.summary.method_note;
}

}  // namespace
