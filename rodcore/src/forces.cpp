#include "rodcore/forces.hpp"

#include <cmath>

#include "rodcore/brownian.hpp"
#include "rodcore/contact.hpp"
#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"
#include "rodcore/reconstruction.hpp"
#include "rodcore/thermal.hpp"

namespace rodcore {
namespace {

std::string num(double x) { return message_number(x); }

// The closure projection of a thermal run (docs/thermal.md, "Closure in a run"):
// two chord-Newton steps (one checked), on sweeps of at most 0.2 rad per Magnus
// substep, whose holonomy is within ~1e-4 of the output's (0.05 rad) for the
// 158-bp DNA rod at 300 K; at 4x fewer substeps.
constexpr int kClosureSteps = 2;
constexpr double kClosureTurn = 0.2;
// The overdamped rod's steps are few and long (100 ps for the kilobase ring) and each moves
// the closure of a ring of many persistence lengths far outside the chord steps' reach: up
// to 6 Newton steps, re-linearised, to 1e-10 (each a sweep, O(N), against the step's solve).
constexpr int kBrownianClosureSteps = 6;
constexpr double kBrownianClosureTolerance = 1e-10;

class ContactForce final : public Force {
 public:
  ContactForce(std::unique_ptr<SelfContact> contact, const MaterialField& mf)
      : contact_(std::move(contact)), mf_(mf) {}
  void add_to_rhs(const double* y, double* dydt) override { contact_->add_to_rhs(y, mf_, dydt); }
  void add_energy(const double* y, EnergyParts& e) override {
    e.contact = contact_->energy(y);
    e.has_contact = true;
  }

 private:
  std::unique_ptr<SelfContact> contact_;
  const MaterialField& mf_;
};

class LangevinFriction final : public Bath {
 public:
  explicit LangevinFriction(LangevinBath bath) : bath_(std::move(bath)) {}
  void step(long step, double* y, double* anchor) override {
    bath_.apply(step, y);
    // The anchor's quaternion back on the unit sphere (the RK4 part keeps it there only to O(dt^5)).
    if (anchor) {
      const Quat q = quat_normalized({anchor[0], anchor[1], anchor[2], anchor[3]});
      for (int k = 0; k < 4; ++k) anchor[k] = q[k];
    }
  }

 private:
  LangevinBath bath_;
};

class OverdampedStep final : public Bath {
 public:
  explicit OverdampedStep(std::unique_ptr<BrownianStep> step) : step_(std::move(step)) {}
  void step(long step, double* y, double* anchor) override { step_->apply(step, y, anchor); }

 private:
  std::unique_ptr<BrownianStep> step_;
};

}  // namespace

std::unique_ptr<Force> make_contact_force(const Scene& sc, const RodSystem& system, bool closed,
                                          double period) {
  const ContactPotential p = contact_potential(sc.contact);  // the reader checked its keys
  if (!closed && period < 2.0 * p.cutoff)
    throw InputError(sc.source + ": [contact]: the box-periodic rod's period " + num(period) +
                     " is shorter than twice the contact cut-off " + num(p.cutoff) +
                     " (from contact.diameter and contact.barrier_kT): the rod would touch its own images");
  std::unique_ptr<SelfContact> contact;
  try {
    contact = std::make_unique<SelfContact>(system.points(), sc.rod.length, p, closed);
  } catch (const InputError& e) {
    throw InputError(sc.source + ": " + e.what());
  }
  return std::make_unique<ContactForce>(std::move(contact), system.material());
}

std::unique_ptr<Bath> make_bath(const Scene& sc, const RodSystem& system) {
  const Thermal& th = sc.thermal;
  const std::size_t N = system.points();
  if (sc.solver.time == TimeMethod::langevin)
    return std::make_unique<LangevinFriction>(
        LangevinBath(system.material(), sc.rod.length / static_cast<double>(N), th.kT,
                     th.friction_translational, th.friction_rotational, sc.solver.dt, th.seed));
  if (sc.solver.time == TimeMethod::brownian) {
    const RodSystem* s = &system;
    return std::make_unique<OverdampedStep>(std::make_unique<BrownianStep>(
        N, sc.rod.length, system.material(), system.elastic().op(),
        [s](const double* y, double* f) { s->rhs(y, f); }, th.friction_translational, th.friction_rotational,
        th.kT, sc.solver.dt, th.seed,
        sc.solver.exact_noise ? BrownianStep::Noise::exact : BrownianStep::Noise::implicit_euler));
  }
  return nullptr;
}

std::string bath_note(const Scene& sc) {
  const Thermal& th = sc.thermal;
  const std::string friction = " at kT = " + num(th.kT) + ", friction translational [along, across] = [" +
                               num(th.friction_translational[0]) + ", " + num(th.friction_translational[1]) +
                               "], rotational [about, across] = [" + num(th.friction_rotational[0]) + ", " +
                               num(th.friction_rotational[1]) + "] per length";
  if (sc.solver.time == TimeMethod::brownian) return "; overdamped (Brownian) rod" + friction;
  if (sc.solver.time == TimeMethod::langevin) return "; Langevin rod" + friction;
  return "";
}

ClosureHold::ClosureHold(const Scene& sc, const MaterialField& mf)
    : projector_(static_cast<std::size_t>(sc.rod.points), sc.rod.length, mf, kClosureTurn),
      every_(sc.thermal.closure_interval),
      newton_(sc.solver.time == TimeMethod::brownian) {}

void ClosureHold::hold_box_of(const double* y, const RigidMotion& g0) {
  box_ = box_motion(projector_.holonomy(y), g0);
}

double ClosureHold::gap(const double* y, const RigidMotion& g0) {
  return projector_.size(ClosureProjector::defect(projector_.holonomy(y), holonomy_for(box_, g0)));
}

// "Reaches" to 1e-9 of the interval: a fixed step's accumulated time lands a
// few ulps short of the multiple it stands for (and a frame there).
bool ClosureHold::after_step(double t_prev, double t, double* y, double* anchor) {
  auto index = [this](double time) { return std::floor(time / every_ + 1e-9); };
  if (every_ > 0.0 && index(t) == index(t_prev)) return false;
  const RigidMotion g0{{anchor[0], anchor[1], anchor[2], anchor[3]}, {anchor[4], anchor[5], anchor[6]}};
  const RigidMotion target = holonomy_for(box_, g0);
  return (newton_ ? projector_.project(y, target, kBrownianClosureSteps, kBrownianClosureTolerance, true)
                  : projector_.project(y, target, kClosureSteps))
             .steps > 0;
}

}  // namespace rodcore
