// The general rod material (docs/numerics.md, "General material"): a
// symmetric positive-definite 6 x 6 stiffness K on e = (Gamma - Gamma0,
// Omega - Omega0), rows/cols Gamma1..3, Omega1..3, a symmetric
// positive-definite 3 x 3 inertia I and a density rho > 0, uniform or per grid
// point. The stress is n = (K e)[0..2] = dW/dGamma, the moment
// m = (K e)[3..5] = dW/dOmega.
//
// A scene's Material (scene.hpp) is validated and turned into the form the
// RHS kernel reads (MaterialField) here, once. The kind decides which
// compile-time specialisation of the one kernel runs (rhs.cpp):
//   diagonal   K = diag(C, D), I diagonal, rho = 1, uniform: the paper's Eqs 11-14;
//   uniform    any other uniform K, I, rho;
//   per_point  K, I, rho given at every grid point.
#pragma once
#include <array>
#include <cstddef>
#include <string>
#include <vector>

#include "rodcore/scene.hpp"

namespace rodcore {

enum class MaterialKind { diagonal, uniform, per_point };

// Index of (r, c) in the 21 unique entries of a symmetric 6 x 6 matrix and in
// the 6 unique entries of a symmetric 3 x 3 one (row-major upper triangle).
constexpr int sym6(int r, int c) {
  const int a = r < c ? r : c, b = r < c ? c : r;
  return a * 6 - a * (a - 1) / 2 + (b - a);
}
constexpr int sym3(int r, int c) {
  const int a = r < c ? r : c, b = r < c ? c : r;
  return a * 3 - a * (a - 1) / 2 + (b - a);
}

struct MaterialField {
  MaterialKind kind = MaterialKind::diagonal;
  std::size_t N = 0;
  // Uniform kinds (diagonal included): full matrices, row-major.
  std::array<double, 36> K{};
  std::array<double, 9> I{}, Iinv{};
  double rho = 1.0;
  // per_point: structure of arrays, row k of N values at [k * N + i]:
  // K_s 21 rows (sym6), I_s and Iinv_s 6 rows (sym3), rho_s and irho_s 1 row.
  std::vector<double> K_s, I_s, Iinv_s, rho_s, irho_s;

  // The material at point i (any kind): K (36, row-major), I (9), rho.
  void K_at(std::size_t i, double* K36) const;
  void I_at(std::size_t i, double* I9) const;
  double rho_at(std::size_t i) const;
};

// Validates `m` for a grid of N points and returns the kernel's form. Errors
// (InputError) name the key (material.K, material.I, material.rho) or the
// dataset and point of the material file, and say what is allowed.
MaterialField resolve_material(const Material& m, std::size_t N);

// Checks of one matrix; `where` starts the message ("material.K", "file
// 'm.h5': dataset 'K' at point 3"). K: 36 values, I: 9, row-major. A K or I
// that is symmetric to 1e-12 relative is made exactly symmetric in place (the
// energy is then conserved exactly by the semi-discrete system).
void check_stiffness(double* K36, const std::string& where);
void check_inertia(double* I9, const std::string& where);

// Which material kind `m` resolves to, without the N-dependent checks.
MaterialKind material_kind(const Material& m);

// Largest characteristic speed of the equations' principal part, max over
// points of sqrt(lambda_max(M^-1 K)), M = diag(rho, rho, rho, I): the wave
// speed of the CFL estimate (equals max sqrt C_i, sqrt(D_i / I_i) for a
// diagonal material with rho = 1).
double max_wave_speed(const MaterialField& mf);

// Empty if the material keeps the planar invariant subspace whose non-zero
// strains are e_k, k in `kept` (3 indices of 0..5), and angular velocity
// omega_a (a = 0 or 1): no entry of K couples a kept strain to a zero one,
// and I has no off-diagonal entry in row/column a. Otherwise the reason,
// naming the first offending entry.
std::string planar_coupling(const MaterialField& mf, const std::array<int, 3>& kept, int axis);

}  // namespace rodcore
