// The forces of a scene's rod (force.hpp), each the adapter of its physics file
// to the System (system.hpp):
//   make_contact_force  [contact]: the self-contact forces in every right-hand
//                       side and their energy (contact.hpp);
//   make_bath           the friction and noise of solver.time: "langevin" the
//                       exact Ornstein-Uhlenbeck step (thermal.hpp), "brownian"
//                       the overdamped step (brownian.hpp), else none;
//   ClosureHold         thermal.keep_closure: the box motion of the initial
//                       state restored every thermal.closure_interval
//                       (closure.hpp; docs/thermal.md, "Closure in a run").
#pragma once
#include <memory>
#include <string>

#include "rodcore/closure.hpp"
#include "rodcore/force.hpp"
#include "rodcore/scene.hpp"
#include "rodcore/system.hpp"

namespace rodcore {

// closed: a ring (else box-periodic with the lab-frame `period`, the length of
// r(L) - r(0)). Throws InputError naming the scene if the rod cannot carry the
// contact potential (a period shorter than twice the cut-off, a grid that does
// not fit it).
std::unique_ptr<Force> make_contact_force(const Scene& scene, const RodSystem& system, bool closed,
                                          double period);

// Null for the deterministic schemes. The overdamped step evaluates the
// System's right-hand side (its forces included): `system` must outlive it.
std::unique_ptr<Bath> make_bath(const Scene& scene, const RodSystem& system);

// What the bath of a thermal scene is, for the run's thermal note ("" if none).
std::string bath_note(const Scene& scene);

class ClosureHold final : public AfterStep {
 public:
  ClosureHold(const Scene& scene, const MaterialField& mf);
  // Holds the box motion of the 12 N state y whose frame at s = 0 is g0.
  void hold_box_of(const double* y, const RigidMotion& g0);
  // The size of the defect of y's holonomy against the box held (closure.hpp).
  double gap(const double* y, const RigidMotion& g0);
  // At the end of the first step that reaches each multiple of the interval
  // (every step for 0): a function of the step's times only, so a resumed run
  // projects where the uninterrupted one did.
  bool after_step(double t_prev, double t, double* y, double* anchor) override;

 private:
  ClosureProjector projector_;
  RigidMotion box_;
  double every_;
  bool newton_;  // the overdamped rod's long steps: Newton steps re-linearised
};

}  // namespace rodcore
