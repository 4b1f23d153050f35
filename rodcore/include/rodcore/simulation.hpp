// Running a scene: the problem (Scene) is separate from the solver
// (spatial operator + time integrator) and from the output handlers
// (callbacks that receive Frames). Dedalus-style separation.
#pragma once
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "rodcore/checkpoint.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

// What an output handler sees at one output time. Pointers are valid only
// during the callback. Optional parts are present only if the scene asked.
struct Frame {
  int index = 0;
  double t = 0.0;
  std::size_t N = 0;
  const double* y = nullptr;  // 12*N state, layout of state.hpp
  std::optional<double> energy;
  std::map<std::string, double> energy_parts;  // kinetic_translational, kinetic_rotational,
                                               // shear, extension, bend, twist
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
};

class Simulation {
 public:
  explicit Simulation(const Scene& scene);  // throws InputError
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  using FrameHandler = std::function<void(const Frame&)>;
  using ProgressHandler = std::function<void(double t, double t_end)>;

  // Integrate to output.t_end, calling on_frame at each output time
  // (including t = 0). Throws NumericalError on bad numbers; the frames
  // already handed to on_frame are complete.
  RunSummary run(const FrameHandler& on_frame, const ProgressHandler& progress = {});

  // Checkpoints (checkpoint.hpp): after every accepted step, once the frames
  // up to that time are delivered, `due()` is asked; when it says yes the
  // run point is handed to `save`, which may throw to stop the run.
  struct CheckpointHooks {
    std::function<bool()> due;
    std::function<void(const Checkpoint&)> save;
  };
  void set_checkpoint_hooks(CheckpointHooks hooks);
  // The next run() continues from `checkpoint` (no frame before
  // checkpoint.next_frame is delivered again). Throws InputError if it does
  // not belong to this scene.
  void resume_from(const Checkpoint& checkpoint);

  // The scene as run: solver.space and solver.time resolved from "auto".
  const Scene& scene() const;
  std::vector<double> grid() const;  // s_i
  const std::vector<double>& state() const;  // current 12*N state
  double time() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace rodcore
