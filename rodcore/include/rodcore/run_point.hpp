// A run at a step boundary: what the solver core hands out and takes back to
// continue a run bit for bit (Simulation::checkpoint, Simulation::resume_from).
// The file that holds one, and the observers that write it, are checkpoint.hpp's
// (the scene layer): this header is the data alone.
#pragma once
#include <limits>
#include <string>
#include <vector>

#include "rodcore/scene.hpp"

namespace rodcore {

// Everything a time integrator needs to continue exactly from a step
// boundary: restoring it and stepping on gives the same bits as never having
// stopped.
struct IntegratorState {
  double t = 0.0;
  double dt_next = 0.0;            // the step the controller will try next
  std::vector<double> y, f;        // y(t) and f(t, y) (FSAL stage / Hermite slope)
  std::vector<double> controller;  // step-size controller memory (scheme-specific)
  long steps = 0, rejected = 0, rhs_evaluations = 0;
};

struct Checkpoint {
  std::string scene;                          // checkpoint_scene_text() of the run's scene
  TimeMethod method = TimeMethod::automatic;  // solver.time as run (never automatic in a file)
  IntegratorState integrator;                 // t, dt_next, y, f, controller memory, counters
  int next_frame = 0;                         // output frames 0 .. next_frame-1 are already written
  double E0 = std::numeric_limits<double>::quiet_NaN();  // energy at t = 0
  double energy_drift = 0.0;                             // largest relative drift over the frames so far
  double wall_seconds = 0.0;                             // wall time spent on the run so far
  std::string reduced;  // "" (full 12-row state) or "omega2"/"omega1" (reduced planar system)
};

}  // namespace rodcore
