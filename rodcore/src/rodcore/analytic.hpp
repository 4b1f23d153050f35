// Closed-form results of the paper, in ONE place (dimensionless units),
// reused by initial-condition kinds, tests and the Python layer.
//
// Field order of the 12 values returned at a point: the state rows of
// state.hpp, i.e. gamma1..3, omega1..3, Gamma1..3, Omega1..3.
#pragma once
#include <array>
#include <string>

#include "rodcore/dna_units.hpp"  // default material (D1, C3) from dna_models

namespace rodcore::analytic {

using Fields = std::array<double, 12>;

// Eq 26 (Eq 39 with kappa = k): frequency of the large-amplitude bend-shear
// wave of a straight rod, branch = +1 ("plus") or -1 ("minus"):
//   w = 1/2 { sqrt(kappa^2 (sqrt D1 + 1)^2 + Gamma03^2)
//            +- sqrt(kappa^2 (sqrt D1 - 1)^2 + Gamma03^2) }.
double dispersion(double kappa, double D1, double Gamma03, int branch);

// Eq 27: shear / bend energy ratio Gamma_perp^2 / (D1 Omega_perp^2) of the
// exact wave, [w^2 - kappa^2 D1]^2 / (D1 kappa^2 Gamma03^2).
double energy_ratio(double w, double kappa, double D1, double Gamma03);

// The exact twisted-rod wave, Eq 24, in the checked form of
// docs/numerics.md ("Eq 24 as implemented"): with theta = w t - k s,
// sigma = -1 for kappa_p = k + Omega03, sigma = +1 for kappa_m = k - Omega03,
// a_w = w Gamma03 A / (w^2 - D1 kappa^2),
//   Gamma = ( A cos th,  sigma A sin th,  Gamma03 )
//   gamma = ( -kappa A / w cos th,  -sigma kappa A / w sin th,  0 )
//   omega = ( sigma a_w cos th,  a_w sin th,  0 )
//   Omega = ( -sigma kappa a_w / w cos th,  -kappa a_w / w sin th,  Omega03 )
// It solves the full nonlinear Eqs 11-14 for any A when C1 = C2 = 1 and
// I1 = I2 = 1 (the paper's dimensionless material), any D1 = D2, C3, D3, I3.
struct TwistedWave {
  double A = 0.5;  // shear amplitude Gamma_1^A
  double k = 2.0;  // wavenumber
  double Gamma03 = 1.0;
  double Omega03 = 1.0;
  double D1 = dna_units::D_star[0];
  std::string kappa_branch = "p";  // "p": kappa = k + Omega03, "m": k - Omega03
  int omega_branch = +1;           // +1: w_+, -1: w_-

  double kappa() const;
  double sigma() const;  // -1 for "p", +1 for "m"
  double w() const;      // Eq 26
  double a_w() const;
  double period() const;  // 2 pi / w
  Fields at(double s, double t) const;
  Fields d_dt(double s, double t) const;  // exact time derivative
};

// The asymptotic bend-shear wave of an intrinsically straight, untwisted rod,
// Eqs 40-45, polarisation (gamma1, Gamma1, omega2, Omega2, gamma3, dGamma3),
// with the corrections found in docs/numerics.md: theta = w t - k s,
// a = eps (1 + eps), g = (w^2 - D1 k^2) / (w Gamma03),
//   omega2 = a sin th,        Omega2 = -(k/w) a sin th,
//   Gamma1 = g a cos th,      gamma1 = -(k/w) g a cos th,
//   gamma3 = C3 k Gamma03 eps^2 / (4 w (w^2 - C3 k^2)) cos 2th,
//   Gamma3 = Gamma03 - Gamma03 eps^2 / (4 (w^2 - C3 k^2)) cos 2th.
// (The paper prints the opposite sign for Gamma1, gamma1 and k^2 C3^2 for
// k^2 C3 in Eq 44-45.) Valid for C1 = I2 = 1 (paper's material).
struct UntwistedWave {
  double eps = 0.1;
  double k = 2.0;
  double Gamma03 = 1.0;
  double D1 = dna_units::D_star[0];
  double C3 = dna_units::C_star[2];
  int omega_branch = +1;

  double w() const;  // Eq 39
  double g() const;
  Fields at(double s, double t) const;
};

}  // namespace rodcore::analytic
