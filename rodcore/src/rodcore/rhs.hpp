// The right-hand side of the dimensionless rod equations (paper Eqs 11-14),
// internal frame, periodic in s, general diagonal C, D, I and an intrinsic
// shape Gamma0(s), Omega0(s) that may vary along s:
//
//   d gamma/dt = C d(Gamma - Gamma0)/ds + Omega x C(Gamma - Gamma0) - omega x gamma
//   d omega/dt = I^-1 [ D d(Omega - Omega0)/ds + Omega x D(Omega - Omega0)
//                       + Gamma x C(Gamma - Gamma0) - omega x I omega ]
//   d Gamma/dt = d gamma/ds + Omega x gamma - omega x Gamma
//   d Omega/dt = d omega/ds - omega x Omega
//
// This is the ONE implementation of the physics; integrators, tests and any
// reduced system call it. State layout: state.hpp (12 rows of N).
#pragma once
#include <array>
#include <cstddef>
#include <vector>

#include "rodcore/operators.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

class RodRHS {
 public:
  // `op` must outlive this object. Throws InputError for a bad intrinsic
  // shape (wrong size or non-finite values) or non-positive I.
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
  // 2 for the omega1 polarisation. Needs a uniform intrinsic shape.
  void reduced(int planar, const std::array<int, 6>& rows, const double* y6, double* f6) const;

  const Material& material() const { return material_; }
  const DerivativeOperator& op() const { return op_; }
  // Intrinsic shape at every grid point, component-major (3 N each).
  const std::vector<double>& Gamma0() const { return Gamma0_; }
  const std::vector<double>& Omega0() const { return Omega0_; }

 private:
  std::size_t N_;
  Material material_;
  const DerivativeOperator& op_;
  std::vector<double> Gamma0_, Omega0_;          // 3 N each
  std::vector<double> dGamma0_ds_, dOmega0_ds_;  // same operator applied once
  std::size_t stride_ = 0;                       // row stride of dy_ds_ (>= N)
  mutable std::vector<double> dy_ds_;            // 12 rows of stride_
  mutable std::vector<double> dy6_;              // 6 N work array of reduced()
  std::vector<int> nonzero_rows_;                // empty: differentiate all rows
  bool uniform_ = true;                          // uniform intrinsic shape: fast kernel
};

// Intrinsic shape of `rod` expanded to 3 N component-major values (uniform
// Gamma0/Omega0 or the per-point arrays). Throws InputError on a wrong size.
std::vector<double> intrinsic_Gamma0(const Rod& rod);
std::vector<double> intrinsic_Omega0(const Rod& rod);

}  // namespace rodcore
