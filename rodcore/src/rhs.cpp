#include "rodcore/rhs.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "rodcore/error.hpp"
#include "rodcore/state.hpp"

namespace rodcore {
namespace {

std::vector<double> expand(const Vec3& uniform, const std::vector<double>& varying, int N,
                           const char* name) {
  const std::size_t n = static_cast<std::size_t>(N);
  std::vector<double> out(3 * n);
  if (varying.empty()) {
    for (int c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < n; ++i) out[c * n + i] = uniform[c];
  } else {
    if (varying.size() != 3 * n)
      throw InputError(std::string("rod.") + name + "_s: expected 3 N = " + std::to_string(3 * n) +
                       " values (N = rod.points), got " + std::to_string(varying.size()));
    out = varying;
  }
  for (std::size_t j = 0; j < out.size(); ++j)
    if (!std::isfinite(out[j]))
      throw InputError(std::string("rod.") + name + ": non-finite value at component " +
                       std::to_string(j / n) + ", point " + std::to_string(j % n));
  return out;
}

}  // namespace

std::vector<double> intrinsic_Gamma0(const Rod& rod) {
  return expand(rod.Gamma0, rod.Gamma0_s, rod.points, "Gamma0");
}
std::vector<double> intrinsic_Omega0(const Rod& rod) {
  return expand(rod.Omega0, rod.Omega0_s, rod.points, "Omega0");
}

RodRHS::RodRHS(const Rod& rod, const Material& material, const DerivativeOperator& op)
    : N_(op.N()), material_(material), op_(op) {
  if (static_cast<std::size_t>(rod.points) != N_)
    throw InputError("RodRHS: rod.points (" + std::to_string(rod.points) +
                     ") differs from the operator's N (" + std::to_string(N_) + ")");
  for (int c = 0; c < 3; ++c) {
    if (!(material.I[c] > 0.0) || !std::isfinite(material.I[c]))
      throw InputError("material.I: all three components must be positive and finite");
    if (!std::isfinite(material.C[c]) || !std::isfinite(material.D[c]))
      throw InputError("material.C and material.D must be finite");
  }
  Gamma0_ = intrinsic_Gamma0(rod);
  Omega0_ = intrinsic_Omega0(rod);
  dGamma0_ds_.assign(3 * N_, 0.0);
  dOmega0_ds_.assign(3 * N_, 0.0);
  // Uniform shapes have zero derivative exactly; only differentiate varying ones.
  if (!rod.Gamma0_s.empty()) op.apply(Gamma0_.data(), dGamma0_ds_.data(), 3);
  if (!rod.Omega0_s.empty()) op.apply(Omega0_.data(), dOmega0_ds_.data(), 3);
  dy_ds_.assign(12 * N_, 0.0);
}

void RodRHS::set_nonzero_rows(std::vector<int> rows) {
  for (int r : rows)
    if (r < 0 || r >= 12) throw InputError("RodRHS::set_nonzero_rows: row " + std::to_string(r) + " not in 0..11");
  nonzero_rows_ = std::move(rows);
  std::fill(dy_ds_.begin(), dy_ds_.end(), 0.0);  // the skipped rows' derivative is zero
}

void RodRHS::operator()(const double* y, double* dydt) const {
  const std::size_t N = N_;
  if (nonzero_rows_.empty()) {
    op_.apply(y, dy_ds_.data(), 12);
  } else {
    for (int r : nonzero_rows_) op_.apply(y + r * N, dy_ds_.data() + r * N, 1);
  }

  const double C1 = material_.C[0], C2 = material_.C[1], C3 = material_.C[2];
  const double D1 = material_.D[0], D2 = material_.D[1], D3 = material_.D[2];
  const double I1 = material_.I[0], I2 = material_.I[1], I3 = material_.I[2];
  const double iI1 = 1.0 / I1, iI2 = 1.0 / I2, iI3 = 1.0 / I3;

  const double* g1 = y + 0 * N; const double* g2 = y + 1 * N; const double* g3 = y + 2 * N;
  const double* w1 = y + 3 * N; const double* w2 = y + 4 * N; const double* w3 = y + 5 * N;
  const double* G1 = y + 6 * N; const double* G2 = y + 7 * N; const double* G3 = y + 8 * N;
  const double* O1 = y + 9 * N; const double* O2 = y + 10 * N; const double* O3 = y + 11 * N;
  const double* d = dy_ds_.data();
  const double *dg1 = d + 0 * N, *dg2 = d + 1 * N, *dg3 = d + 2 * N;
  const double *dw1 = d + 3 * N, *dw2 = d + 4 * N, *dw3 = d + 5 * N;
  const double *dG1 = d + 6 * N, *dG2 = d + 7 * N, *dG3 = d + 8 * N;
  const double *dO1 = d + 9 * N, *dO2 = d + 10 * N, *dO3 = d + 11 * N;
  const double *G01 = Gamma0_.data(), *G02 = G01 + N, *G03 = G01 + 2 * N;
  const double *O01 = Omega0_.data(), *O02 = O01 + N, *O03 = O01 + 2 * N;
  const double *dG01 = dGamma0_ds_.data(), *dG02 = dG01 + N, *dG03 = dG01 + 2 * N;
  const double *dO01 = dOmega0_ds_.data(), *dO02 = dO01 + N, *dO03 = dO01 + 2 * N;
  double *fg1 = dydt + 0 * N, *fg2 = dydt + 1 * N, *fg3 = dydt + 2 * N;
  double *fw1 = dydt + 3 * N, *fw2 = dydt + 4 * N, *fw3 = dydt + 5 * N;
  double *fG1 = dydt + 6 * N, *fG2 = dydt + 7 * N, *fG3 = dydt + 8 * N;
  double *fO1 = dydt + 9 * N, *fO2 = dydt + 10 * N, *fO3 = dydt + 11 * N;

  // The 48 row pointers never overlap (y, dy_ds_, the intrinsic shape and
  // dydt are distinct arrays); saying so lets GCC vectorise the loop
  // (measured: bench/, docs/performance.md).
#pragma GCC ivdep
  for (std::size_t i = 0; i < N; ++i) {
    // Internal forces n = C (Gamma - Gamma0) and moments m = D (Omega - Omega0).
    const double n1 = C1 * (G1[i] - G01[i]), n2 = C2 * (G2[i] - G02[i]), n3 = C3 * (G3[i] - G03[i]);
    const double m1 = D1 * (O1[i] - O01[i]), m2 = D2 * (O2[i] - O02[i]), m3 = D3 * (O3[i] - O03[i]);
    const double a1 = w1[i], a2 = w2[i], a3 = w3[i];   // omega
    const double b1 = g1[i], b2 = g2[i], b3 = g3[i];   // gamma
    const double P1 = O1[i], P2 = O2[i], P3 = O3[i];   // Omega
    const double Q1 = G1[i], Q2 = G2[i], Q3 = G3[i];   // Gamma

    // Eq 11: balance of force.
    fg1[i] = C1 * (dG1[i] - dG01[i]) + (P2 * n3 - P3 * n2) - (a2 * b3 - a3 * b2);
    fg2[i] = C2 * (dG2[i] - dG02[i]) + (P3 * n1 - P1 * n3) - (a3 * b1 - a1 * b3);
    fg3[i] = C3 * (dG3[i] - dG03[i]) + (P1 * n2 - P2 * n1) - (a1 * b2 - a2 * b1);

    // Eq 12: balance of torque, divided by the diagonal I.
    const double Iw1 = I1 * a1, Iw2 = I2 * a2, Iw3 = I3 * a3;
    fw1[i] = iI1 * (D1 * (dO1[i] - dO01[i]) + (P2 * m3 - P3 * m2) + (Q2 * n3 - Q3 * n2) -
                    (a2 * Iw3 - a3 * Iw2));
    fw2[i] = iI2 * (D2 * (dO2[i] - dO02[i]) + (P3 * m1 - P1 * m3) + (Q3 * n1 - Q1 * n3) -
                    (a3 * Iw1 - a1 * Iw3));
    fw3[i] = iI3 * (D3 * (dO3[i] - dO03[i]) + (P1 * m2 - P2 * m1) + (Q1 * n2 - Q2 * n1) -
                    (a1 * Iw2 - a2 * Iw1));

    // Eq 13: compatibility of velocity and strain.
    fG1[i] = dg1[i] + (P2 * b3 - P3 * b2) - (a2 * Q3 - a3 * Q2);
    fG2[i] = dg2[i] + (P3 * b1 - P1 * b3) - (a3 * Q1 - a1 * Q3);
    fG3[i] = dg3[i] + (P1 * b2 - P2 * b1) - (a1 * Q2 - a2 * Q1);

    // Eq 14: compatibility of angular velocity and curvature.
    fO1[i] = dw1[i] - (a2 * P3 - a3 * P2);
    fO2[i] = dw2[i] - (a3 * P1 - a1 * P3);
    fO3[i] = dw3[i] - (a1 * P2 - a2 * P1);
  }
}

}  // namespace rodcore
