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
#include <string>
#include <vector>

#include "rodcore/error.hpp"
#include "rodcore/observer.hpp"
#include "rodcore/run_point.hpp"  // IntegratorState, Checkpoint
#include "rodcore/scene.hpp"

namespace rodcore {

inline constexpr int kCheckpointFormat = 1;

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
