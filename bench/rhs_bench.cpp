// Cost of the right-hand side (Eqs 11-14) and of one adaptive step, per grid
// point, for both spatial operators, N = 32 .. 131072; and the RHS by
// material kind (MaterialRHS, N = 158, 1000, 1024; bench/material.py runs it
// against the base build and writes docs/performance.md's table).
//
//   rodbench --benchmark_filter=RHS     (items_per_second = grid-point updates/s)
//
// One "grid-point update" = all 12 components of dy/dt at one point,
// derivative included. The state is a smooth, non-trivial rod state (the
// exact twisted wave, Eq 24) so no branch or denormal shortcut applies.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "rodcore/analytic.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/reduced_planar.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/scene.hpp"

namespace {

struct Setup {
  rodcore::Rod rod;
  rodcore::Material mat;
  std::unique_ptr<rodcore::DerivativeOperator> op;
  std::unique_ptr<rodcore::RodRHS> rhs;
  std::vector<double> y, f;

  Setup(const char* space, std::size_t N) {
    rod.length = 2.0 * std::numbers::pi;
    rod.points = static_cast<int>(N);
    rod.Gamma0 = {0.0, 0.0, 1.0};
    rod.Omega0 = {0.0, 0.0, 1.0};
    op = rodcore::make_derivative_operator(*rodcore::from_string<rodcore::SpaceMethod>(space), N, rod.length);
    rhs = std::make_unique<rodcore::RodRHS>(rod, mat, *op);
    rodcore::analytic::TwistedWave w;
    w.A = 0.3;
    w.k = 3.0;
    y.assign(12 * N, 0.0);
    f.assign(12 * N, 0.0);
    for (std::size_t i = 0; i < N; ++i) {
      const auto v = w.at(rod.length * static_cast<double>(i) / static_cast<double>(N), 0.0);
      for (int r = 0; r < 12; ++r) y[r * N + i] = v[r];
    }
  }
};

void RHS(benchmark::State& state, const char* space) {
  const auto N = static_cast<std::size_t>(state.range(0));
  Setup s(space, N);
  for (auto _ : state) {
    (*s.rhs)(s.y.data(), s.f.data());
    benchmark::DoNotOptimize(s.f.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(N));
  state.counters["N"] = static_cast<double>(N);
}

// Only the derivative operator on 12 rows: how much of the RHS is d/ds.
void Derivative(benchmark::State& state, const char* space) {
  const auto N = static_cast<std::size_t>(state.range(0));
  Setup s(space, N);
  for (auto _ : state) {
    s.op->apply(s.y.data(), s.f.data(), 12);
    benchmark::DoNotOptimize(s.f.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(N));
  state.counters["N"] = static_cast<double>(N);
}

// One accepted DOP853 step (12 RHS evaluations + error norm + bookkeeping)
// with a fixed tolerance; the step is restarted from the same state each time.
void Step(benchmark::State& state, const char* space) {
  const auto N = static_cast<std::size_t>(state.range(0));
  Setup s(space, N);
  rodcore::OdeSystem sys;
  sys.n = 12 * N;
  rodcore::RodRHS* rhs = s.rhs.get();
  sys.f = [rhs](double, const double* y, double* f) { (*rhs)(y, f); };
  rodcore::IntegratorOptions io;
  io.rtol = io.atol = 1e-6;
  // A step well inside the stability region at every N (the step size does
  // not change the cost of a step).
  io.dt = 0.5 / s.op->max_wavenumber();
  auto integ = rodcore::make_time_integrator(rodcore::TimeMethod::dop853, sys, io);
  for (auto _ : state) {
    state.PauseTiming();
    integ->reset(0.0, s.y.data());
    state.ResumeTiming();
    integ->step(1e9);
    benchmark::DoNotOptimize(integ->y().data());
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(N));
  state.counters["N"] = static_cast<double>(N);
}

// The P3 wave (untwisted rod, k = 2, eps = 0.5, paper Sec 5.2) integrated to
// t = 10 with DOP853 at rtol = atol = 1e-10: the full 12-row system vs the
// reduced planar system (reduced_planar.hpp). Arg 0: N; `reduced` selects.
void PlanarRun(benchmark::State& state, const char* space, bool reduced) {
  const auto N = static_cast<std::size_t>(state.range(0));
  rodcore::Rod rod;
  rod.length = 2.0 * std::numbers::pi;
  rod.points = static_cast<int>(N);
  rod.Gamma0 = {0.0, 0.0, 1.0};
  rod.Omega0 = {0.0, 0.0, 0.0};
  rodcore::Material mat;
  auto op =
      rodcore::make_derivative_operator(*rodcore::from_string<rodcore::SpaceMethod>(space), N, rod.length);
  rodcore::RodRHS rhs(rod, mat, *op);
  rodcore::analytic::UntwistedWave w;
  w.eps = 0.5;
  w.k = 2.0;
  std::vector<double> y0(12 * N);
  for (std::size_t i = 0; i < N; ++i) {
    const auto v = w.at(rod.length * static_cast<double>(i) / static_cast<double>(N), 0.0);
    for (int r = 0; r < 12; ++r) y0[r * N + i] = v[r];
  }
  std::unique_ptr<rodcore::PlanarRHS> planar;
  rodcore::OdeSystem sys;
  std::vector<double> start = y0;
  if (reduced) {
    planar = std::make_unique<rodcore::PlanarRHS>(rhs);
    start.resize(6 * N);
    planar->reduce(y0.data(), start.data());
    sys.n = 6 * N;
    sys.f = [&](double, const double* y, double* f) { (*planar)(y, f); };
  } else {
    sys.n = 12 * N;
    sys.f = [&](double, const double* y, double* f) { rhs(y, f); };
  }
  rodcore::IntegratorOptions io;
  io.rtol = io.atol = 1e-10;
  io.dt = 0.01;
  long steps = 0;
  for (auto _ : state) {
    auto integ = rodcore::make_time_integrator(rodcore::TimeMethod::dop853, sys, io);
    integ->reset(0.0, start.data());
    while (integ->t() < 10.0) integ->step(10.0);
    steps = integ->steps();
    benchmark::DoNotOptimize(integ->y().data());
  }
  state.counters["steps"] = static_cast<double>(steps);
  state.counters["N"] = static_cast<double>(N);
}

// RHS cost by material kind (material.hpp), same state as RHS above:
// "diagonal" the paper's diag(C, D), diagonal I (must cost what RHS costs);
// "coupled" a uniform full K (every entry non-zero) and non-diagonal I;
// "per_point" K, I, rho at every point (a smooth variation of "coupled").
rodcore::Material bench_material(const std::string& kind, std::size_t N) {
  rodcore::Material m;
  if (kind == "diagonal") return m;
  std::vector<double> K(36), I = {1.0, 0.1, 0.05, 0.1, 1.2, 0.08, 0.05, 0.08, 2.0};
  const double d[6] = {1.0, 1.0, 1.19, 1.21, 1.21, 2.02};
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) K[r * 6 + c] = r == c ? d[r] : 0.03 + 0.01 * (r + c);
  if (kind == "coupled") {
    m.K = K;
    m.I_full = I;
    return m;
  }
  for (std::size_t i = 0; i < N; ++i) {
    const double w =
        1.0 + 0.1 * std::sin(2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(N));
    for (double k : K) m.K_s.push_back(w * k);
    for (double v : I) m.I_s.push_back(w * v);
    m.rho_s.push_back(w);
  }
  return m;
}

void MaterialRHS(benchmark::State& state, const char* space, const char* kind) {
  const auto N = static_cast<std::size_t>(state.range(0));
  Setup s(space, N);
  const rodcore::Material mat = bench_material(kind, N);
  rodcore::RodRHS rhs(s.rod, mat, *s.op);
  for (auto _ : state) {
    rhs(s.y.data(), s.f.data());
    benchmark::DoNotOptimize(s.f.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(N));
  state.counters["N"] = static_cast<double>(N);
}

void material_sizes(benchmark::internal::Benchmark* b) {
  for (long n : {158L, 1000L, 1024L}) b->Arg(n);
}

void sizes(benchmark::internal::Benchmark* b) {
  for (long n = 32; n <= 131072; n *= 2) b->Arg(n);
  b->Arg(158);
  b->Arg(1000);
  b->Arg(100000);
}

}  // namespace

BENCHMARK_CAPTURE(RHS, fd4, "fd4")->Apply(sizes);
BENCHMARK_CAPTURE(RHS, spectral, "spectral")->Apply(sizes);
BENCHMARK_CAPTURE(MaterialRHS, fd4_diagonal, "fd4", "diagonal")->Apply(material_sizes);
BENCHMARK_CAPTURE(MaterialRHS, fd4_coupled, "fd4", "coupled")->Apply(material_sizes);
BENCHMARK_CAPTURE(MaterialRHS, fd4_per_point, "fd4", "per_point")->Apply(material_sizes);
BENCHMARK_CAPTURE(MaterialRHS, spectral_diagonal, "spectral", "diagonal")->Apply(material_sizes);
BENCHMARK_CAPTURE(MaterialRHS, spectral_coupled, "spectral", "coupled")->Apply(material_sizes);
BENCHMARK_CAPTURE(MaterialRHS, spectral_per_point, "spectral", "per_point")->Apply(material_sizes);
BENCHMARK_CAPTURE(Derivative, fd4, "fd4")->Apply(sizes);
BENCHMARK_CAPTURE(Derivative, spectral, "spectral")->Apply(sizes);
BENCHMARK_CAPTURE(Step, fd4, "fd4")->Apply(sizes);
BENCHMARK_CAPTURE(Step, spectral, "spectral")->Apply(sizes);

BENCHMARK_CAPTURE(PlanarRun, fd4_full, "fd4", false)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(PlanarRun, fd4_reduced, "fd4", true)->Arg(256)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(PlanarRun, spectral_full, "spectral", false)->Arg(64)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(PlanarRun, spectral_reduced, "spectral", true)->Arg(64)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
