// Self-contact: the rod cannot pass through itself (docs/topology.md, "Self-contact").
//
// The energy is the line-line repulsion of the continuum rod,
//   U = 1/2 int int_{|s - s'| > s_ex} psi(|r(s) - r(s')|) ds ds',
//   psi(r) = psi0 (1 - r^2 / d_c^2)^3 for r < d_c, 0 beyond
// (an energy per length squared; zero with its first two derivatives at the cut-off d_c,
// so the force is smooth and the energy of an NVE run is conserved to the integrator's
// order), summed on the grid: beads r_b at every `stride`-th grid point, each of weight
// w = stride h, U = sum_{pairs} w^2 psi(|r_a - r_b|) (the midpoint rule of the double
// integral, second order in w / d_c). Two straight rods crossing at right angles at axis
// distance rho have, in the continuum, the energy
//   U_perp(rho) = 2 pi int_rho^d_c psi(r) r dr = (pi / 4) psi0 d_c^2 (1 - rho^2 / d_c^2)^4,
// at an angle gamma U_perp / sin gamma. The scene gives the effective diameter d (the
// diameter of hard rods with the same second virial coefficient, isotropically averaged:
// Stigter's definition, which Rybenkov, Cozzarelli & Vologodskii, PNAS 90:5307 (1993)
// measured for DNA) and the barrier B = U_perp(0) / kT; then
//   psi0 = 4 B kT / (pi d_c^2),   d = d_c f(B),
//   f(B) = (4 / pi) int_0^(pi/2) sin^2(g) int_0^1 [1 - exp(-B (1 - x^2)^4 / sin g)] dx dg.
//
// Pairs closer than s_ex = (pi / 2) d_c along the rod are left out: a straight rod's
// neighbours within d_c must not repel, and a rod bent with radius >= d_c / 2 brings no
// point beyond s_ex closer than d_c. The pairs are found with a cell list of cell size
// d_c (hashed, so memory is O(N) whatever the rod's extent): O(N).
//
// The state holds strains and velocities, not positions. At every evaluation the bead
// positions are reconstructed from the strains alone (Reconstructor: the curve of the output,
// the closure and the topology), from the frame (identity, origin) at s = 0: the energy depends only on
// distances and the body-frame force R_i^T F_i only on relative positions and frames, so the anchor r(0, t),
// q(0, t) (integrated with the state only for the output, simulation.cpp) is not needed. A closed rod's
// polygon joins its last point to its first; a box-periodic rod (r(s + L) = r(s) + P) also meets its periodic
// images.
#pragma once
#include <cstddef>
#include <memory>
#include <vector>

#include "rodcore/material.hpp"
#include "rodcore/reconstruction.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

// f(B) above: the effective diameter over the cut-off for a barrier of B kT.
double contact_diameter_ratio(double barrier_kT);

// The potential of a scene's [contact], resolved (dimensionless).
struct ContactPotential {
  double cutoff = 0.0;   // d_c
  double psi0 = 0.0;     // energy per length^2 at r = 0
  double exclude = 0.0;  // s_ex: pairs closer along s are left out
  int stride = 1;        // beads at every stride-th grid point
};
// Throws InputError for settings the rod cannot use (naming the contact.* key).
ContactPotential contact_potential(const Contact& contact);

class SelfContact {
 public:
  // closed: a ring (the polygon closes on itself); otherwise box-periodic. Throws
  // InputError if the grid does not fit the potential (stride, bead spacing, length).
  SelfContact(std::size_t N, double L, const ContactPotential& potential, bool closed);

  // Energy and lab-frame forces (N x 3, zero away from the beads) of the centreline
  // r (N + 1 points: r_N = r_0 + P; for a ring r_N is not used).
  double forces(const double* r, double* F);
  // The contact energy of a state y (12 N, layout of state.hpp).
  double energy(const double* y);
  // dgamma/dt += R_i^T F_i / (rho_i h) at the beads; returns the energy.
  double add_to_rhs(const double* y, const MaterialField& mf, double* dydt);

  // The last sweep's centreline (N + 1 points) and smallest bead distance of any
  // included pair (infinity when no pair is within the cut-off).
  const std::vector<double>& centerline() const { return r_; }
  double min_distance() const { return min_distance_; }
  const ContactPotential& potential() const { return p_; }

 private:
  // fills r_ (and with frames the directors D_) from the strains of y
  void sweep(const double* y, bool frames);
  std::size_t N_;
  double h_;
  ContactPotential p_;
  bool closed_;
  std::size_t M_;                       // beads
  long exclude_pts_;                    // pairs with grid distance < this are left out
  std::unique_ptr<Reconstructor> rec_;  // the run's own reconstruction of the centreline
  std::vector<double> r_, F_, D_;
  // the cell list
  std::vector<long> cell_;  // 3 M cell coordinates
  std::vector<int> head_, next_;
  double min_distance_ = 0.0;
};

}  // namespace rodcore
