#include "rodcore/stability.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"

namespace rodcore {

double linear_spectral_radius(const RodRHS& rhs) {
  const std::size_t N = rhs.N();
  if (rhs.material_field().kind == MaterialKind::per_point)
    throw InputError("linear_spectral_radius: needs a uniform material (a per-point material gives no "
                     "constant-coefficient linearisation)");
  const auto& G0 = rhs.Gamma0();
  const auto& O0 = rhs.Omega0();
  for (std::size_t i = 1; i < N; ++i)
    for (int c = 0; c < 3; ++c)
      if (G0[c * N + i] != G0[c * N] || O0[c * N + i] != O0[c * N])
        throw InputError("linear_spectral_radius: needs a uniform intrinsic shape");

  std::vector<double> rest(12 * N, 0.0);
  for (int c = 0; c < 3; ++c)
    for (std::size_t i = 0; i < N; ++i) {
      rest[(6 + c) * N + i] = G0[c * N];
      rest[(9 + c) * N + i] = O0[c * N];
    }
  // Lowest mode j = 1: cos and sin on the grid, and its effective wavenumber
  // from the operator itself (d/ds cos = -k sin).
  std::vector<double> cosm(N), sinm(N), dcos(N);
  for (std::size_t i = 0; i < N; ++i) {
    const double th = 2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(N);
    cosm[i] = std::cos(th);
    sinm[i] = std::sin(th);
  }
  rhs.op().apply(cosm.data(), dcos.data(), 1);
  double cc = 0.0, ss = 0.0, ds = 0.0;
  for (std::size_t i = 0; i < N; ++i) {
    cc += cosm[i] * cosm[i];
    ss += sinm[i] * sinm[i];
    ds += dcos[i] * sinm[i];
  }
  const double k1 = -ds / ss;
  if (!(k1 > 0.0)) throw Error("linear_spectral_radius: the operator does not differentiate the lowest mode");

  Eigen::Matrix<double, 12, 12> A0, A1;
  const double eps = 1e-3;  // exact up to round-off: the RHS is quadratic in y
  std::vector<double> yp(rest), ym(rest), fp(12 * N), fm(12 * N);
  for (int c = 0; c < 12; ++c) {
    yp = rest;
    ym = rest;
    for (std::size_t i = 0; i < N; ++i) {
      yp[c * N + i] += eps * cosm[i];
      ym[c * N + i] -= eps * cosm[i];
    }
    rhs(yp.data(), fp.data());
    rhs(ym.data(), fm.data());
    for (int r = 0; r < 12; ++r) {
      double pc = 0.0, ps = 0.0;
      for (std::size_t i = 0; i < N; ++i) {
        const double d = (fp[r * N + i] - fm[r * N + i]) / (2.0 * eps);
        pc += d * cosm[i];
        ps += d * sinm[i];
      }
      A0(r, c) = pc / cc;
      A1(r, c) = -(ps / ss) / k1;
    }
  }

  const double kmax = rhs.op().max_wavenumber();
  constexpr int kSamples = 256;
  double radius = 0.0;
  Eigen::ComplexEigenSolver<Eigen::Matrix<std::complex<double>, 12, 12>> solver;
  for (int m = 0; m <= kSamples; ++m) {
    const double k = kmax * static_cast<double>(m) / kSamples;
    const Eigen::Matrix<std::complex<double>, 12, 12> M =
        A0.cast<std::complex<double>>() + std::complex<double>(0.0, k) * A1.cast<std::complex<double>>();
    solver.compute(M, false);
    radius = std::max(radius, solver.eigenvalues().cwiseAbs().maxCoeff());
  }
  return radius;
}

void check_step_limit(const Scene& sc, const RodRHS& rhs, const StepLimit& limit) {
  if (!std::isfinite(limit.bound)) return;
  const auto num = [](double x) { return message_number(x); };
  const DerivativeOperator& op = rhs.op();
  const double speed = std::max(1.0, max_wave_speed(rhs.material_field()));
  const bool uniform = sc.rod.Gamma0_s.empty() && sc.rod.Omega0_s.empty() &&
                       rhs.material_field().kind != MaterialKind::per_point;
  const double lambda = uniform ? linear_spectral_radius(rhs) : speed * op.max_wavenumber();
  const double dt_max = limit.bound / lambda;
  if (!(sc.solver.dt > dt_max)) return;
  const std::string bound = num(limit.bound);
  throw NumericalError(sc.source + ": solver.dt = " + num(sc.solver.dt) + " exceeds the " + limit.scheme +
                       " stability limit " + num(dt_max) +
                       (uniform ? " (" + bound + " / spectral radius " + num(lambda) +
                                      " of the equations linearised about the rest state, "
                                : " (estimate: " + bound + " / (max wave speed " + num(speed) +
                                      " x max wavenumber " + num(op.max_wavenumber()) + "), ") +
                       op.name() + "); use solver.dt <= " + num(dt_max * (1.0 - 5e-6)) + limit.otherwise);
}

}  // namespace rodcore
