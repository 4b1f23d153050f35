// Checkpoints: never lose a run (docs/reliability.md).
//
// A checkpoint holds everything needed to continue a run from a step
// boundary so that the continued run equals an uninterrupted one bit for bit
// (the integrator's state including its step-size controller memory, the next
// output frame, the energy at t = 0 for the drift check; the s = 0 anchor of
// the reconstruction, when there is one, is part of the integrated state y).
// It is an HDF5 file OUT.h5.ckpt next to the output OUT.h5:
//   attributes  format, scene (resolved TOML), method, t, dt_next,
//               next_frame, E0, energy_drift, wall_seconds, steps, rejected,
//               rhs_evaluations, reduced ("" full system, or the planar
//               polarisation "omega2" / "omega1" whose 6 rows y holds)
//   datasets    y, f (state and its time derivative at t), controller
// written to OUT.h5.ckpt.tmp, synced to disk and renamed over the previous
// one, so a kill during the write never spoils the last good checkpoint.
//
// Simulation::checkpoint() makes one, Simulation::resume_from() continues
// from one, the observer CheckpointObserver hands them to a function during
// a run and CheckpointWriter writes them to the file (when: their `due`
// predicate; rodsim's is a wall-clock timer or a stop signal,
// rodcore/cli/signals.hpp).
#pragma once
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "rodcore/error.hpp"
#include "rodcore/observer.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

inline constexpr int kCheckpointFormat = 1;

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

// OUT.h5 -> OUT.h5.ckpt
std::string checkpoint_path(const std::string& output_path);

// The scene as the checkpoint records it: the resolved TOML with the
// checkpoint interval left out (it may differ between the run and its resume).
std::string checkpoint_scene_text(const Scene& scene);

// Atomic write (temp file, fsync, rename). Throws Error if it cannot write.
void write_checkpoint(const std::string& path, const Checkpoint& checkpoint);

// Throws InputError naming the file if it is missing, not a checkpoint, of
// another format version, or damaged.
Checkpoint read_checkpoint(const std::string& path);

// Throws InputError if `checkpoint` was not made by a run of `scene`
// (names the first differing line of the resolved scenes).
void check_checkpoint_matches(const Checkpoint& checkpoint, const Scene& scene,
                              const std::string& checkpoint_file);

// The observer that takes checkpoints: after every accepted step whose
// frames are delivered (and while frames remain), it asks `due()`; when it
// says yes it hands sim.checkpoint() to `save`, which may throw to stop the
// run. The one rule of when a checkpoint is complete and worth taking.
class CheckpointObserver : public Observer {
 public:
  CheckpointObserver(std::function<bool()> due, std::function<void(const Checkpoint&)> save);
  void stepped(const Simulation& sim) override;

 protected:
  virtual void save(const Checkpoint& checkpoint);

 private:
  std::function<bool()> due_;
  std::function<void(const Checkpoint&)> save_;
};

// The observer that writes checkpoints to a file: a CheckpointObserver whose
// save writes the checkpoint to `path` (atomically) and then calls
// `written(checkpoint)`, which may throw to stop the run (rodsim does after a
// stop signal). A run that ends (finished or failed numerically) removes the
// file: continuing would meet the same error, and a stale checkpoint must
// never be paired with a later output.
class CheckpointWriter : public CheckpointObserver {
 public:
  CheckpointWriter(std::string path, std::function<bool()> due,
                   std::function<void(const Checkpoint&)> written = {});
  void finished(const Simulation& sim, const RunSummary& summary) override;
  void failed(const Simulation& sim, const std::string& message) override;
  const std::string& path() const { return path_; }

 protected:
  void save(const Checkpoint& checkpoint) override;

 private:
  std::string path_;
  std::function<void(const Checkpoint&)> written_;
};

}  // namespace rodcore
