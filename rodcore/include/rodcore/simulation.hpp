// Running a scene: the problem (Scene) is separate from the solver and from
// what is done with the result (observers, observer.hpp). OpenMM's Context:
// inside, the rod's System (its elastic right-hand side on a spatial operator
// plus a list of forces: friction and noise, contact, closure; src/rodcore/
// system.hpp) advanced by one time integrator behind one protocol
// (src/rodcore/integrators.hpp).
//
//   rodcore::Scene scene = rodcore::read_scene_file("dna158.toml");  // scene_io.hpp
//   rodcore::Simulation sim(scene);
//   sim.add_observer(std::make_shared<rodcore::H5Writer>("out.h5", sim));  // h5_writer.hpp
//   sim.add_observer(rodcore::on_frame([](const rodcore::Frame& f) { /* ... */ }));
//   rodcore::RunSummary summary = sim.run();      // or: sim.step_to(t) in pieces
//   sim.time(); sim.state(); sim.energy();         // the state now
//
// The solver works in the paper's dimensionless variables only (Sec 2.2);
// scenes in DNA units (e.g. dna_planar's A_v_A_per_ps) are converted when
// the initial state is made, by the scene layer (library rodcore_scene,
// exported as rodcore::scene). Two members are defined there, because they
// need the scene's initial-condition kinds or its TOML text:
// Simulation(const Scene&) and checkpoint(). The rest is the solver core
// (rodcore::core).
#pragma once
#include <array>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "rodcore/observer.hpp"
#include "rodcore/run_point.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

// A dimensionless initial state: the 12 N fields on the grid s_i = i L / N
// (layout of state.hpp, internal frame) and the lab frame of the rod at
// s = 0, t = 0 (used only when the scene reconstructs centerline/directors).
struct InitialState {
  std::vector<double> y;
  std::array<double, 4> q0{1.0, 0.0, 0.0, 0.0};  // unit quaternion (w, x, y, z) of the directors at s = 0
  Vec3 r0{0.0, 0.0, 0.0};                        // r(0, 0)
};

class Simulation {
 public:
  // The initial state made from scene.initial (its kind; scene layer). A
  // scene built in code may leave rod.length/points to the kind (dna_planar).
  // With [thermal] sample_initial, an equilibrium sample is added to it (both
  // constructors; thermal.hpp). Throws InputError.
  explicit Simulation(const Scene& scene);
  // The initial state given; scene.initial is then only recorded (e.g. in the
  // output file). Throws InputError (sizes, non-finite values, settings).
  Simulation(const Scene& scene, InitialState initial);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // Observers are called in the order added, after the scene's own checks.
  void add_observer(std::shared_ptr<Observer> observer);

  // Advance to time t (>= time()). Every output frame (output.frames equally
  // spaced times 0..output.t_end) the integrator passes on the way is handed
  // to the observers, frame 0 on the first call. Steps are taken toward
  // max(t, output.t_end) and never shortened to stop at t: the state at t
  // comes from the integrator's continuous extension, so stepping in pieces
  // gives the same numbers as one run. Throws NumericalError on bad numbers
  // (the frames already delivered are complete).
  void step_to(double t);

  // Integrate to the last output time (step_to), then the observers'
  // finished(). Returns the summary (also: summary()).
  RunSummary run();
  RunSummary summary() const;  // of the steps taken so far

  // Checkpoints (run_point.hpp; their file: checkpoint.hpp). checkpoint(): the run point now; valid
  // between steps once their frames are delivered (as in Observer::stepped).
  // resume_from(): the next step_to()/run() continues from `checkpoint` (no
  // frame before checkpoint.next_frame is delivered again); throws
  // InputError if it does not belong to this scene.
  Checkpoint checkpoint() const;
  void resume_from(const Checkpoint& checkpoint);

  // The scene as run: solver.space and solver.time resolved from automatic;
  // given_scene(): as given (automatic kept; what checkpoints record).
  const Scene& scene() const;
  const Scene& given_scene() const;
  std::vector<double> grid() const;          // s_i
  const std::vector<double>& state() const;  // 12 N state at time()
  double time() const;
  // How far the integrator has got (>= time(): steps are not shortened to stop at t).
  double integrator_time() const;
  int frames_delivered() const;        // output frames handed out so far
  double frame_time(int index) const;  // time of output frame `index`
  // Diagnostics of the state now (Appendix A), computed on demand.
  double energy() const;
  std::map<std::string, double> energy_parts() const;
  // 2 KE / (6 N) of the state now: the kinetic temperature in energy units
  // (docs/thermal.md).
  double kinetic_kT() const;
  // The right-hand side of Eqs (11)-(14) for this scene's rod and material
  // (with [contact] the self-contact force included, contact.hpp):
  // dydt = f(y), both 12 N values in the layout of state.hpp.
  void rhs(const double* y, double* dydt) const;

 private:
  Checkpoint run_point() const;  // checkpoint() without the scene text (core)
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// f(t, t_end) after every accepted step once its frames are delivered: t the
// integrator's time, t_end the last output time (an observer made of a
// function, observer.hpp, that asks the Simulation how far it has got).
std::shared_ptr<FunctionObserver> on_progress(std::function<void(double t, double t_end)> f);

}  // namespace rodcore
