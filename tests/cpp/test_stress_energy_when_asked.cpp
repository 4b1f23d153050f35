// Energy is computed only where it is asked for (docs/numerics.md): without energy
// output and without a drift bound, frames carry no energy and the summary's
// drift is the end-to-end one, |E(t_end) - E(0)| / |E(0)|, evaluated here
// independently from the delivered first and last states.
#include <gtest/gtest.h>

#include "physics_test_util.hpp"
#include "rodcore/diagnostics.hpp"

namespace {

using namespace rodcore;

TEST(EnergyWhenAsked, OnlyFirstAndLastFrameWhenNotAsked) {
  Scene sc = rodtest::twisted_wave_scene(32, "p", "plus");
  sc.output.frames = 9;
  sc.output.t_end = 1.0;
  sc.solver.rtol = sc.solver.atol = 1e-5;  // a visible drift
  const auto r = rodtest::run_scene(sc);
  EXPECT_TRUE(r.energy.empty());
  const double h = sc.rod.length / 32.0;
  std::vector<double> Gamma0(3 * 32, 0.0), Omega0(3 * 32, 0.0);
  for (int i = 0; i < 32; ++i) {
    Gamma0[2 * 32 + i] = 1.0;
    Omega0[2 * 32 + i] = 1.0;
  }
  const double E0 = energy_parts(r.y.front().data(), 32, h, sc.material, Gamma0, Omega0).total();
  const double E1 = energy_parts(r.y.back().data(), 32, h, sc.material, Gamma0, Omega0).total();
  ASSERT_GT(std::abs(E1 - E0), 0.0);
  EXPECT_DOUBLE_EQ(r.summary.energy_drift, std::abs(E1 - E0) / std::abs(E0));

  // Asked for: every frame, and the drift is the largest over them.
  sc.output.energy = true;
  const auto a = rodtest::run_scene(sc);
  ASSERT_EQ(a.energy.size(), 9u);
  double worst = 0.0;
  for (double e : a.energy) worst = std::max(worst, std::abs(e - a.energy[0]) / a.energy[0]);
  EXPECT_DOUBLE_EQ(a.summary.energy_drift, worst);
}

}  // namespace
