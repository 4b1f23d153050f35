// What a run reports, and to whom: the observer interface of Simulation.
//
// A Simulation integrates; everything else a run does is an observer called
// from its loop (OpenMM's reporters, Dedalus' output handlers): the checks of
// the scene's [checks] (non-finite values, folding, energy drift, director
// norms; added by Simulation itself, first), the HDF5 writer (h5_writer.hpp),
// checkpoints (checkpoint.hpp), rodsim's progress bar, and Python callbacks.
// Order of the calls for each accepted step of the integrator:
//   step(sim, view)  right after the step, before any frame it completes
//                    (a guard that throws here keeps that frame unwritten);
//   frame(sim, f)    for each output time the step passed (dense output);
//   stepped(sim)     once the frames up to the integrator's time are all
//                    delivered: a checkpoint taken now is complete.
// started() comes before frame 0 (or before the first step of a resumed run),
// finished() after the last frame of Simulation::run(), failed() when a
// NumericalError stops the run (then rethrown). An observer may throw to stop.
#pragma once
#include <cstddef>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rodcore/state.hpp"

namespace rodcore {

class Simulation;

// What an observer sees at one output time. Pointers are valid only during
// the call. Optional parts are present only if the scene asked.
struct Frame {
  int index = 0;
  double t = 0.0;
  std::size_t N = 0;
  const double* y = nullptr;                   // 12*N state, layout of state.hpp
  std::optional<double> energy;                // when output.energy or output.energy_parts
  std::map<std::string, double> energy_parts;  // kinetic_translational, kinetic_rotational,
                                               // shear, extension, bend, twist
  // The energy as the run computes it for its checks, and its relative drift
  // |E - E(0)| / |E(0)|: at every frame when the output or a finite
  // checks.max_energy_drift asks, else at the first and the last frame only.
  std::optional<double> checked_energy;
  std::optional<double> energy_drift;
  const double* centerline = nullptr;  // N x 3, row-major (point, xyz); lab frame
  const double* directors = nullptr;   // N x 3 x 3, [i][xyz][k] = component xyz of d_k
  double max_director_norm_error = 0.0;
  // Closure of the reconstructed rod over one period (only with centerline
  // or directors): end_to_end = r(L) - r(0) in the lab frame, end_rotation =
  // angle (rad) of the rotation R(0)^T R(L). A closed ring or a ligated DNA
  // circle has both ~0; a straight periodic rod has end_to_end = its length
  // along d3 and end_rotation = its total twist mod 2 pi.
  std::optional<Vec3> end_to_end;
  std::optional<double> end_rotation;
  // A thermal scene ([thermal]): 2 KE / (6 N), the kinetic temperature in
  // energy units (docs/thermal.md).
  std::optional<double> kinetic_kT;
  // A closed rod (a ring): its linking number, twist and writhe (topology.hpp,
  // docs/topology.md). Lk is NaN when the frame's ribbon cannot be resolved.
  struct Topology {
    double Lk, Tw, Wr;
  };
  std::optional<Topology> topology;
};

// The integrated state right after an accepted step. `y` holds `rows.size()`
// rows of N values (rows[k] is the state row, layout of state.hpp: all 12, or
// the 6 of a planar polarisation when the reduced system runs), then the 7
// values of the s = 0 anchor (quaternion, position) when the scene
// reconstructs; `n` values in all.
struct StepView {
  double t = 0.0;
  std::size_t N = 0;
  const double* y = nullptr;
  std::size_t n = 0;
  const std::vector<int>* rows = nullptr;
};

struct RunSummary {
  long steps = 0;
  long rejected = 0;
  long rhs_evaluations = 0;
  double wall_seconds = 0.0;
  double energy_drift = 0.0;  // max relative |E - E0| / |E0| over the output frames where E is
                              // computed: all with output.energy(_parts) or a finite
                              // checks.max_energy_drift, else the first and the last
  std::string method;         // e.g. "spectral+dop853"
  bool reduced = false;       // the reduced planar system was used (to the end)
  std::string reduce_note;    // why the run is reduced or not (solver.reduce)
  std::string method_note;    // how solver.space / solver.time were chosen ("auto" or as given)
  std::string thermal_note;   // a thermal scene: what its sample did ("" otherwise)
};

class Observer {
 public:
  virtual ~Observer() = default;
  virtual void started(const Simulation&) {}
  virtual void step(const Simulation&, const StepView&) {}
  virtual void frame(const Simulation&, const Frame&) {}
  virtual void stepped(const Simulation&) {}
  virtual void finished(const Simulation&, const RunSummary&) {}
  virtual void failed(const Simulation&, const std::string& /*message*/) {}
};

// An observer made of plain functions, for a use that needs no class of its
// own; an empty function is not called.
//   sim.add_observer(rodcore::on_frame([&](const rodcore::Frame& f) { times.push_back(f.t); }));
struct FunctionObserver : Observer {
  std::function<void(const Simulation&)> on_started;
  std::function<void(const Simulation&, const StepView&)> on_step;
  std::function<void(const Simulation&, const Frame&)> on_frame;
  std::function<void(const Simulation&)> on_stepped;
  std::function<void(const Simulation&, const RunSummary&)> on_finished;
  std::function<void(const Simulation&, const std::string&)> on_failed;
  void started(const Simulation& sim) override;
  void step(const Simulation& sim, const StepView& view) override;
  void frame(const Simulation& sim, const Frame& frame) override;
  void stepped(const Simulation& sim) override;
  void finished(const Simulation& sim, const RunSummary& summary) override;
  void failed(const Simulation& sim, const std::string& message) override;
};

// f(frame) at every output frame (the old Simulation::run(on_frame)).
std::shared_ptr<FunctionObserver> on_frame(std::function<void(const Frame&)> f);

}  // namespace rodcore
