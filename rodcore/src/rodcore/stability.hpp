// Exact linear stability bound for explicit fixed-step schemes, and the one
// check of a scene's fixed step against its integrator's limit.
//
// About the rest state y_rest (gamma = omega = 0, Gamma = Gamma0, Omega =
// Omega0, uniform) the semi-discrete system is linear with constant
// coefficients: dy/dt = A0 y + A1 dy/ds. On a Fourier mode whose discrete
// derivative is i k (k the operator's effective wavenumber, 0 <= k <= kmax)
// its eigenvalues are those of the 12 x 12 matrix A0 + i k A1. The spectral
// radius is the max over k; for the paper's rods it exceeds the wave-speed
// estimate c kmax (c = max sqrt C_i, sqrt(D_i/I_i)) by the O(1) frequencies of
// the lower-order terms, by up to 1.6x on the DNA rod at N = 158
// (docs/performance.md, bench/stress/stability.py).
//
// A0 and A1 are not written down a second time: they are read off the ONE
// RodRHS by central differences (exact, the RHS is quadratic) on the lowest
// Fourier mode.
#pragma once
#include "rodcore/integrators.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

// max |eigenvalue| of the linearisation about the uniform rest state, over
// 0 <= k <= op.max_wavenumber() (sampled densely, endpoints included; the
// continuous range contains every discrete mode, so the bound is safe).
// Any uniform material (coupled K, full I, rho). Throws InputError if the
// intrinsic shape varies along s or the material is per point.
double linear_spectral_radius(const RodRHS& rhs);

// Throws NumericalError if solver.dt exceeds `limit` (the integrator's,
// integrators.hpp) for the rod's fastest linear mode: limit.bound / lambda,
// lambda the exact radius above for a uniform intrinsic shape and a uniform
// material (any K, I, rho), else the estimate c_max k_max (c_max the largest
// characteristic speed over the points, material.hpp, at least 1; it leaves out
// the lower-order terms, which raised the true radius by up to 1.6x on the DNA
// rod). No limit (infinite bound): nothing to check.
void check_step_limit(const Scene& scene, const RodRHS& rhs, const StepLimit& limit);

}  // namespace rodcore
