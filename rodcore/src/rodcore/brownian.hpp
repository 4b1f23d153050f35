// The overdamped (Brownian) rod, solver.time = "brownian" (docs/thermal.md,
// "The overdamped rod"): no inertia, the velocities are the forces over the
// friction. Per unit length, with body-frame frictions Z = diag(Z_t, Z_r)
// (across, across, along d3) and x the configuration (displacements and
// rotation vectors of the points, body frame):
//   Z dx = F(q) dt + (2 kT Z / h)^1/2 dW,   F = (force, torque) per length,
//   dq = D(q) dx  (+ the Ito drift below),
// q = (Gamma, Omega) the strains (the state, as for the inertial rod), D(q) the
// compatibility operator of Eqs 13-14 (rows 6..11 of the RHS with the
// velocities set to dx) and F(q) = -D(q)^T K e the elastic force and torque
// (rows 0..5 of the same RHS at zero velocity, times rho and I): the physics
// is the RHS's, written once (rhs.cpp).
//
// The step is linearly implicit (Gauss-Newton H = D^T K D at the step's start,
// positive semidefinite):
//   (Z + dt H) dx = dt F(q_n) + xi,
//   xi = (2 kT dt / h)^1/2 Z^1/2 eta1 + dt (kT / h)^1/2 D^T K^1/2 eta2,
// so that for the linearised rod x_{n+1} = A^-1 (x_n + Z^-1 xi), A = I + dt M H
// (M = Z^-1 / h, H per rod h D^T K D), and the noise covariance
// 2 kT dt (M + dt M H M / 2) solves A C A^T = C + Sigma for C = kT H^-1: the
// stationary distribution is exactly Boltzmann at any dt, and a stiff mode is
// multiplied by 1 / (1 + lambda dt) per step: L-stable, never a sign flip
// (docs/thermal.md derives it). H is block-banded (cyclic for a periodic or
// closed rod) because d/ds is: it is assembled by 6 x 6 blocks and solved by
// the cyclic block-band Cholesky of block_band.hpp, O(N) per step.
//
// The compatibility update is a midpoint in q, q_{n+1} = q_n + D((q_n + q_{n+1}) / 2) dx:
// the diffusion tensor (kT / h) D M D^T in the strain coordinates depends on q (the cross
// products of D), and the midpoint's mean second-order term is its divergence
// (kT / h) div(D M D^T) dt at small dt -- the Ito drift that makes
// exp(-E / kT) dGamma dOmega stationary, the density the inertial Langevin rod samples
// (docs/thermal.md, "Liouville") -- while at large dt it is bounded by the step's own
// covariance of dx, where an explicit Ito term would grow with dt. The translational and
// rotational mobilities are constant in the body frame and not coupled, so no other drift
// arises.
#pragma once
#include <array>

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <vector>

#include "rodcore/material.hpp"

namespace rodcore {

class DerivativeOperator;

class BrownianStep {
 public:
  // exact: the noise above; implicit_euler: eta1 only (the plain implicit Euler
  // noise, whose stiff modes are too cold by 1 / (1 + lambda dt / 2): a control
  // for the tests, not a scene option).
  enum class Noise { exact, implicit_euler };
  // rhs(y, f): the rod's right-hand side on the 12 N state (self-contact included);
  // op: the banded d/ds it uses (its stencil is read once: the operator must be
  // translation invariant and local, i.e. fd4). friction_*: [along/about d3, across]
  // per length, all > 0.
  BrownianStep(std::size_t N, double L, const MaterialField& mf, const DerivativeOperator& op,
               std::function<void(const double* y, double* f)> rhs,
               std::array<double, 2> friction_translational, std::array<double, 2> friction_rotational,
               double kT, double dt, unsigned long long seed, Noise noise = Noise::exact);
  ~BrownianStep();
  BrownianStep(const BrownianStep&) = delete;
  BrownianStep& operator=(const BrownianStep&) = delete;

  // One step of the 12 N state y (velocity rows zero on entry and on exit) and
  // the s = 0 anchor (q(0), r(0): 7 values after the state, or null); `step`
  // selects the random numbers (philox.hpp counter).
  void apply(long step, double* y, double* anchor);

  // The stencil of d/ds: (offset, weight) pairs, f'_i = sum w f_{i + offset}.
  const std::vector<std::pair<int, double>>& stencil() const { return stencil_; }

 private:
  struct Solver;
  // the parts of one step (apply): the right-hand side dt F at the step's start, the
  // implicit matrix Z + dt D^T K D assembled and factorised at q, the noise added to the
  // right-hand side, and the strains and anchor moved by the solved displacement dx
  Eigen::VectorXd force_rhs(double* y);
  void factorise(const double* y);
  void add_noise(long step, Eigen::VectorXd& b);
  void advance(long step, const Eigen::VectorXd& dx, double* y, double* anchor);
  std::size_t N_;
  double h_, kT_, dt_;
  Noise noise_;
  std::array<std::uint32_t, 2> key_;
  std::function<void(const double*, double*)> rhs_;
  std::vector<std::pair<int, double>> stencil_;
  std::vector<double> K_, LK_, I_, rho_;  // per point (or one): K (36), its Cholesky factor (36), I (9), rho
  bool per_point_;
  std::array<double, 6> Z_;  // (Z_t, Z_r) diagonal, body frame
  std::vector<double> y0_, f_, dx_;
  std::unique_ptr<Solver> solver_;
};

}  // namespace rodcore
