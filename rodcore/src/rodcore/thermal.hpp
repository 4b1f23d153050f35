// The rod at a temperature (docs/thermal.md): a Boltzmann sample of the
// linearised rod, the Ornstein-Uhlenbeck (friction and noise) part of the
// Langevin rod, and the kinetic temperature. Dimensionless throughout: kT in
// the material's energy unit, frictions per unit length (the scene layer
// turns temperature_K and "water" into these numbers, solvent.hpp).
//
// The energy of the discrete rod (diagnostics.hpp) is
//   E = sum_i h [ rho_i |gamma_i|^2 / 2 + omega_i.I_i omega_i / 2 + e_i.K_i e_i / 2 ],
// so its Boltzmann density exp(-E / kT) makes every point independent and
// Gaussian: e_i ~ N(0, kT K_i^-1 / h), gamma_i ~ N(0, kT / (rho_i h)),
// omega_i ~ N(0, kT I_i^-1 / h). The semi-discrete conservative flow keeps
// both E and the volume element dgamma domega dGamma dOmega (its RHS has zero
// divergence, docs/thermal.md), so this density is invariant under it.
#pragma once
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "rodcore/material.hpp"

namespace rodcore {

// 2 KE / (6 N): the kinetic temperature in energy units (equipartition gives
// kT per velocity degree of freedom). y: the 12 N state; h = L / N.
double kinetic_kT(const double* y, std::size_t N, double h, const MaterialField& mf);

// What a sample did, for the run's notes and the tests.
struct ThermalSampleReport {
  int closure_iterations = 0;     // Newton steps that made the holonomy exact (0: linear order only)
  int closure_stages = 0;         // stages of the continuation in the amplitude (0: chord steps sufficed)
  double closure_residual = 0.0;  // |holonomy - the initial state's| after them (rad and length, max)
  bool closure_exact = false;     // residual at round-off (the nonlinear iteration converged)
  int momentum_constraints = 0;   // 3 + 1 (periodic straight or helical rod) or 3 + 3 (closed ring)
  std::string note;               // one line for the run's summary
};

// Adds to the 12 N state y an equilibrium sample of the rod linearised about
// y, at temperature kT, from the random numbers of `seed` (philox.hpp):
//   strains e_i ~ N(0, kT K_i^-1 / h) by the Cholesky factor of every K_i
//   (coupled, per point), gamma_i ~ N(0, kT / (rho_i h)), omega_i ~ N(0, kT I_i^-1 / h);
// then the two conserved things the dynamics could never restore:
//   closure  the holonomy g(0)^-1 g(L) (rotation and translation over one
//            period) of y: the strain sample is conditioned on it, exactly
//            for the linearised rod (projection in the metric K / h), then
//            made exact for the nonlinear reconstruction by chord-Newton
//            steps along the same six directions, or, where those cannot
//            converge (a ring many persistence lengths long), by continuation
//            in the sample's amplitude with Newton steps re-linearised at each
//            trial state (thermal.cpp, close_by_continuation);
//   momenta  zero linear momentum, and zero angular momentum about the
//            axis (all three components for a closed ring): the velocity
//            sample is projected in the mass metric, with the frames of the
//            sampled configuration (exact: momenta are linear in velocities).
// L: rod length; mf: the resolved material.
ThermalSampleReport add_thermal_sample(std::vector<double>& y, double L, const MaterialField& mf, double kT,
                                       unsigned long long seed);

// The friction-and-noise part of the Langevin rod over a time `tau`, solved
// exactly (an Ornstein-Uhlenbeck step) at every point:
//   rho dgamma = -Z_t gamma dt + (2 kT Z_t / h)^1/2 dW,
//   I domega   = -Z_r omega dt + (2 kT Z_r / h)^1/2 dW,
// with body-frame frictions per length Z_t = diag(a, a, z), Z_r likewise
// (across, across, along d3). gamma' = c gamma + s xi per component with
// c = exp(-Z tau / rho), s^2 = kT (1 - c^2) / (rho h); omega' = B omega + S xi
// with B = I^-1/2 exp(-M tau) I^1/2, M = I^-1/2 Z_r I^-1/2, S S^T =
// kT (I^-1 - B I^-1 B^T) / h: the Gaussian velocity density above is
// invariant, and the velocity covariance relaxes at the friction's rates.
class LangevinBath {
 public:
  // friction_translational: [along d3, across], friction_rotational: [about d3, across].
  LangevinBath(const MaterialField& mf, double h, double kT, std::array<double, 2> friction_translational,
               std::array<double, 2> friction_rotational, double tau, unsigned long long seed);
  // One OU step on the velocity rows (0..5) of the 12 N state y; `step`
  // selects the random numbers (philox.hpp counter).
  void apply(long step, double* y) const;

 private:
  std::size_t N_;
  bool per_point_;
  bool noise_;
  std::array<std::uint32_t, 2> key_;
  // Per point (or one, uniform material): translational c, s (3 each) and
  // rotational B, S (3 x 3 row-major each): 24 numbers.
  std::vector<double> coef_;
};

}  // namespace rodcore
