// The right-hand side of the dimensionless rod equations, internal frame,
// periodic in s, for the general material of material.hpp (K, I, rho uniform
// or per grid point) and an intrinsic shape Gamma0(s), Omega0(s) that may vary
// along s. With e = (Gamma - Gamma0, Omega - Omega0), (n, m) = K e:
//
//   d gamma/dt = rho^-1 [ dn/ds + Omega x n ] - omega x gamma
//   d omega/dt = I^-1 [ dm/ds + Omega x m + Gamma x n - omega x I omega ]
//   d Gamma/dt = d gamma/ds + Omega x gamma - omega x Gamma
//   d Omega/dt = d omega/ds - omega x Omega
//
// For K = diag(C, D), diagonal I and rho = 1 these are the paper's Eqs 11-14
// (derivation: docs/numerics.md, "General material"). The derivative acts on
// n and m, so the semi-discrete energy is conserved exactly for s-dependent
// material; for a uniform K, dn/ds = K de/ds is the same thing.
//
// This is the ONE implementation of the physics; integrators, tests and any
// reduced system call it. State layout: state.hpp (12 rows of N).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "rodcore/material.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

class RodRHS {
 public:
  // `op` must outlive this object. Throws InputError for a bad intrinsic
  // shape (wrong size or non-finite values) or a bad material (material.hpp).
  RodRHS(const Rod& rod, const Material& material, const DerivativeOperator& op);

  std::size_t N() const { return N_; }
  std::size_t size() const { return 12 * N_; }
  // dydt = f(y); y and dydt hold 12 N values and must not overlap.
  // No allocation (work arrays are members), so not thread-safe.
  void operator()(const double* y, double* dydt) const;

  // Rows of y that the caller guarantees to be exactly zero need no
  // derivative: with a non-empty list, d/ds is applied only to `rows` (a
  // reduced system, reduced_planar.hpp). Empty list: all 12 rows (default).
  void set_nonzero_rows(std::vector<int> rows);

  // The reduced planar system (reduced_planar.hpp), same kernel with the six
  // out-of-plane rows fixed at zero at compile time: y6 and f6 hold the six
  // kept rows `rows` (state rows) in that order; planar = 1 for the omega2,
  // 2 for the omega1 polarisation. Needs a uniform intrinsic shape and a
  // uniform material.
  void reduced(int planar, const std::array<int, 6>& rows, const double* y6, double* f6) const;

  const Material& material() const { return material_; }
  const MaterialField& material_field() const { return mf_; }
  const DerivativeOperator& op() const { return op_; }
  // Intrinsic shape at every grid point, component-major (3 N each).
  const std::vector<double>& Gamma0() const { return Gamma0_; }
  const std::vector<double>& Omega0() const { return Omega0_; }

 private:
  std::size_t N_;
  Material material_;
  MaterialField mf_;
  const DerivativeOperator& op_;
  std::vector<double> Gamma0_, Omega0_;          // 3 N each
  std::vector<double> dGamma0_ds_, dOmega0_ds_;  // same operator applied once
  std::size_t stride_ = 0;                       // row stride of dy_ds_ (>= N)
  mutable std::vector<double> dy_ds_;            // 12 rows of stride_
  mutable std::vector<double> dy6_;              // 6 N work array of reduced()
  mutable std::vector<double> nm_;               // non-diagonal material: n, m (6 N)
  std::vector<int> nonzero_rows_;                // empty: differentiate all rows
  bool uniform_ = true;                          // uniform intrinsic shape: fast kernel
};

// Intrinsic shape of `rod` expanded to 3 N component-major values (uniform
// Gamma0/Omega0 or the per-point arrays). Throws InputError on a wrong size.
std::vector<double> intrinsic_Gamma0(const Rod& rod);
std::vector<double> intrinsic_Omega0(const Rod& rod);

}  // namespace rodcore
