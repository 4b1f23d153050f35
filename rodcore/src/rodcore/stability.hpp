// Exact linear stability bound for explicit fixed-step schemes.
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
#include "rodcore/rhs.hpp"

namespace rodcore {

// max |eigenvalue| of the linearisation about the uniform rest state, over
// 0 <= k <= op.max_wavenumber() (sampled densely, endpoints included; the
// continuous range contains every discrete mode, so the bound is safe).
// Any uniform material (coupled K, full I, rho). Throws InputError if the
// intrinsic shape varies along s or the material is per point.
double linear_spectral_radius(const RodRHS& rhs);

}  // namespace rodcore
