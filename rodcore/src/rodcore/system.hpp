// The rod's System, in the manner of OpenMM's: the elastic right-hand side of
// Eqs (11)-(14) (RodRHS on its d/ds, rhs.hpp) plus a list of forces, a bath
// and after-step actions (force.hpp); and what a time integrator integrates of
// it (OdeSystem, integrators.hpp): the 12 rows of the state, or only the 6 rows
// of a planar polarisation (reduced_planar.hpp), followed by the 7 values of
// the frame at s = 0 when the System carries that anchor (reconstruction.hpp).
// The run loop (simulation.cpp) and the integrators see the physics only here.
#pragma once
#include <cstddef>
#include <memory>
#include <optional>
#include <vector>

#include "rodcore/diagnostics.hpp"
#include "rodcore/force.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/reduced_planar.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

class RodSystem {
 public:
  // The rod and material of `scene` on its d/ds (solver.space resolved);
  // anchor: the frame at s = 0 is integrated with the state.
  RodSystem(const Scene& scene, bool anchor);
  RodSystem(const RodSystem&) = delete;
  RodSystem& operator=(const RodSystem&) = delete;

  std::size_t points() const { return N_; }
  bool anchored() const { return anchor_; }
  const RodRHS& elastic() const { return *rhs_; }
  const MaterialField& material() const { return rhs_->material_field(); }

  void add_force(std::unique_ptr<Force> force);
  void set_bath(std::unique_ptr<Bath> bath);
  // A step action, called after every accepted step in the order added.
  void add_after_step(std::unique_ptr<AfterStep> action);

  // dy/dt of the 12 N state: the elastic right-hand side, then every force's part.
  void rhs(const double* y, double* dydt) const;
  // The energy and its parts of a 12 N state: elastic and kinetic, and every force's.
  EnergyParts energy_parts(const double* y) const;

  // What the integrator integrates: the full state (nullopt) or a planar
  // polarisation (a System with no force, bath or step action only).
  void integrate(std::optional<Planar> planar);
  const std::optional<Planar>& planar() const { return planar_; }
  const std::vector<int>& rows() const { return rows_; }  // integrated rows -> state rows
  std::size_t full_size() const { return 12 * N_ + (anchor_ ? 7 : 0); }
  // The ODE of what is integrated now. It refers to this System, which must
  // outlive it, and holds until the next integrate().
  OdeSystem ode() const;
  // Integrated state <-> full state (12 N, then the anchor); expand returns y
  // itself for the full system, else a buffer of this System.
  const double* expand(const double* y);
  void reduce(const double* full, double* y) const;
  // The guard of the reduction: the elastic right-hand side at the full state
  // y12 leaves the six rows outside the polarisation exactly zero.
  bool reduction_holds(const double* y12);

 private:
  std::size_t N_;
  double h_;  // grid spacing L / N
  bool anchor_;
  std::unique_ptr<DerivativeOperator> op_;
  std::unique_ptr<RodRHS> rhs_;
  std::vector<std::unique_ptr<Force>> forces_;
  std::unique_ptr<Bath> bath_;
  std::vector<std::unique_ptr<AfterStep>> after_step_;
  std::optional<Planar> planar_;
  std::unique_ptr<PlanarRHS> planar_rhs_;
  std::vector<int> rows_;
  std::vector<double> full_, f_guard_;
};

}  // namespace rodcore
