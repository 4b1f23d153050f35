// What acts on the rod besides its elasticity, in the manner of OpenMM's Force:
// the System (system.hpp) is the rod's elastic right-hand side plus a list of
// these, and the run loop and the integrators know them only through these
// protocols. Three kinds, by where they enter a step:
//   Force      a conservative force: its part of dy/dt in every evaluation of
//              the right-hand side, and its potential energy (self-contact,
//              contact.hpp);
//   Bath       friction and noise: their step over dt on the state, which the
//              integrator composes with the conservative flow ("langevin": the
//              exact Ornstein-Uhlenbeck step, thermal.hpp) or takes as its
//              whole step ("brownian": the overdamped rod, where friction
//              stands in for inertia, brownian.hpp); a System has at most one;
//   AfterStep  called with the new state after every accepted step, before the
//              slope there is formed: a constraint that moves the state back
//              onto a manifold (the closure of a ring, closure.hpp) or a check
//              that stops the run by throwing NumericalError (a strand-passage
//              guard of a closed rod with self-contact belongs here).
// Each sees the 12 N state y (layout of state.hpp) and `anchor`, the 7 values
// of the frame at s = 0 (quaternion, position) that follow it when the System
// carries them, else null. A System with any of them is never reduced to a
// planar subspace (reduced_planar.hpp).
#pragma once
#include "rodcore/diagnostics.hpp"

namespace rodcore {

class Force {
 public:
  virtual ~Force() = default;
  // dydt += this force's part of the right-hand side at y (12 N each).
  virtual void add_to_rhs(const double* y, double* dydt) = 0;
  // Its potential energy at y, into its entry of `e`.
  virtual void add_energy(const double* y, EnergyParts& e) = 0;
};

class Bath {
 public:
  virtual ~Bath() = default;
  // One step over the integrator's dt on y and the anchor, in place; `step`
  // is the index of the step in the run (the random numbers' counter, so a
  // resumed run draws what an uninterrupted one did).
  virtual void step(long step, double* y, double* anchor) = 0;
};

class AfterStep {
 public:
  virtual ~AfterStep() = default;
  // The step [t_prev, t] was accepted and y, anchor are its new state.
  // Returns whether it moved them; throws NumericalError to stop the run.
  virtual bool after_step(double t_prev, double t, double* y, double* anchor) = 0;
};

}  // namespace rodcore
