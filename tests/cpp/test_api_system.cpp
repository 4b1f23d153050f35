// The rod's System (system.hpp) and its protocols (force.hpp), and the one
// stability protocol of the integrators. Independent truths: the integrator's
// own step count and times (an AfterStep sees each accepted step once, in
// order), the elastic right-hand side alone (a Force adds exactly its part),
// and RK4's stability polynomial on the imaginary axis, whose boundary is
// 2 sqrt 2 (the limit the scheme states must lie inside it, by about 1 %).
#include <gtest/gtest.h>

#include <cmath>
#include <complex>
#include <limits>
#include <memory>
#include <numbers>
#include <vector>

#include "rodcore/analytic.hpp"
#include "rodcore/error.hpp"
#include "rodcore/force.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/system.hpp"

namespace {

using namespace rodcore;

constexpr std::size_t kN = 16;

Scene wave_scene() {
  Scene sc;
  sc.rod.length = 2.0 * std::numbers::pi;
  sc.rod.points = static_cast<int>(kN);
  sc.rod.Gamma0 = {0.0, 0.0, 1.0};
  sc.rod.Omega0 = {0.0, 0.0, 0.0};
  sc.solver.space = SpaceMethod::spectral;
  return sc;
}

// The paper's Sec 5.2 wave (k = 2, eps = 0.1) on the grid.
std::vector<double> wave_state(const Scene& sc) {
  analytic::UntwistedWave w;
  w.eps = 0.1;
  w.k = 2.0;
  std::vector<double> y(12 * kN);
  for (std::size_t i = 0; i < kN; ++i) {
    const auto v = w.at(sc.rod.length * static_cast<double>(i) / static_cast<double>(kN), 0.0);
    for (int r = 0; r < 12; ++r) y[r * kN + i] = v[r];
  }
  return y;
}

struct Recorder final : AfterStep {
  std::vector<std::pair<double, double>>* steps;
  long throw_at;
  Recorder(std::vector<std::pair<double, double>>* s, long at) : steps(s), throw_at(at) {}
  bool after_step(double t_prev, double t, double* y, double* anchor) override {
    EXPECT_EQ(anchor, nullptr);  // the System carries no anchor here
    EXPECT_TRUE(std::isfinite(y[0]));
    steps->emplace_back(t_prev, t);
    if (static_cast<long>(steps->size()) == throw_at) throw NumericalError("planted check");
    return false;
  }
};

struct Push final : Force {
  void add_to_rhs(const double*, double* dydt) override { dydt[3] += 1.0; }
  void add_energy(const double*, EnergyParts& e) override {
    e.contact = 2.5;
    e.has_contact = true;
  }
};

std::unique_ptr<TimeIntegrator> integrator(const RodSystem& sys, TimeMethod kind) {
  IntegratorOptions io;
  io.rtol = io.atol = 1e-9;
  io.dt = 0.01;
  return make_time_integrator(kind, sys.ode(), io);
}

TEST(ApiSystem, AnAfterStepSeesEveryAcceptedStepOnceInOrder) {
  const Scene sc = wave_scene();
  for (TimeMethod kind : {TimeMethod::rk4, TimeMethod::dop853}) {
    RodSystem sys(sc, false);
    EXPECT_FALSE(sys.ode().project);  // control: nothing registered, nothing called
    std::vector<std::pair<double, double>> seen;
    sys.add_after_step(std::make_unique<Recorder>(&seen, -1));
    auto integ = integrator(sys, kind);
    integ->reset(0.0, wave_state(sc).data());
    while (integ->t() < 0.5) integ->step(0.5);
    ASSERT_EQ(static_cast<long>(seen.size()), integ->steps()) << to_string(kind);
    EXPECT_EQ(seen.front().first, 0.0);
    for (std::size_t k = 1; k < seen.size(); ++k) EXPECT_EQ(seen[k].first, seen[k - 1].second);
    EXPECT_EQ(seen.back().second, integ->t());
  }
}

TEST(ApiSystem, AnAfterStepThatThrowsStopsTheRun) {
  const Scene sc = wave_scene();
  RodSystem sys(sc, false);
  std::vector<std::pair<double, double>> seen;
  sys.add_after_step(std::make_unique<Recorder>(&seen, 3));
  auto integ = integrator(sys, TimeMethod::rk4);
  integ->reset(0.0, wave_state(sc).data());
  integ->step(1.0);
  integ->step(1.0);
  EXPECT_THROW(integ->step(1.0), NumericalError);
  EXPECT_EQ(seen.size(), 3u);
}

TEST(ApiSystem, AForceAddsExactlyItsPartToTheRhsAndTheEnergy) {
  const Scene sc = wave_scene();
  const std::vector<double> y = wave_state(sc);
  RodSystem plain(sc, false), pushed(sc, false);
  pushed.add_force(std::make_unique<Push>());
  std::vector<double> f0(12 * kN), f1(12 * kN);
  plain.rhs(y.data(), f0.data());
  pushed.rhs(y.data(), f1.data());
  for (std::size_t i = 0; i < 12 * kN; ++i) EXPECT_EQ(f1[i], f0[i] + (i == 3 ? 1.0 : 0.0)) << i;
  const EnergyParts e0 = plain.energy_parts(y.data()), e1 = pushed.energy_parts(y.data());
  EXPECT_FALSE(e0.has_contact);
  EXPECT_EQ(e1.total(), e0.total() + 2.5);
  // The ODE the integrator sees is the same right-hand side.
  std::vector<double> g(12 * kN);
  pushed.ode().f(0.0, y.data(), g.data());
  EXPECT_EQ(g, f1);
  // A planar subspace is not invariant under an arbitrary force: the System refuses it.
  EXPECT_THROW(pushed.integrate(Planar::omega2), Error);
  EXPECT_NO_THROW(plain.integrate(Planar::omega2));
}

TEST(ApiSystem, TheStepLimitsLieInsideTheirSchemesStabilityRegion) {
  const auto rk4_gain = [](double x) {  // |R(i x)|, R the RK4 stability polynomial
    const std::complex<double> z(0.0, x);
    return std::abs(1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0);
  };
  const double boundary = 2.0 * std::sqrt(2.0);
  EXPECT_LE(rk4_gain(boundary), 1.0 + 1e-12);
  EXPECT_GT(rk4_gain(boundary * 1.01), 1.0);  // control: just outside it grows
  const Scene sc = wave_scene();
  const double rk4 = step_limit(TimeMethod::rk4).bound;
  EXPECT_LE(rk4, boundary);
  EXPECT_GT(rk4, 0.985 * boundary);  // a margin of about 1 %
  EXPECT_LE(rk4_gain(rk4), 1.0);
  // The Langevin splitting's conservative part is an RK4 step: the same limit; the adaptive
  // schemes control their step and the overdamped step is implicit: none.
  EXPECT_EQ(step_limit(TimeMethod::langevin).bound, rk4);
  for (TimeMethod none :
       {TimeMethod::rk4_doubling, TimeMethod::dopri5, TimeMethod::dop853, TimeMethod::brownian})
    EXPECT_EQ(step_limit(none).bound, std::numeric_limits<double>::infinity()) << to_string(none);
}

}  // namespace
