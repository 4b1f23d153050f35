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
#pragma once
#include <csignal>
#include <chrono>
#include <limits>
#include <string>

#include "rodcore/error.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

inline constexpr int kCheckpointFormat = 1;

struct Checkpoint {
  std::string scene;           // checkpoint_scene_text() of the run's scene
  std::string method;          // solver.time, e.g. "dop853"
  IntegratorState integrator;  // t, dt_next, y, f, controller memory, counters
  int next_frame = 0;          // output frames 0 .. next_frame-1 are already written
  double E0 = std::numeric_limits<double>::quiet_NaN();  // energy at t = 0
  double energy_drift = 0.0;   // largest relative drift over the frames so far
  double wall_seconds = 0.0;   // wall time spent on the run so far
  std::string reduced;         // "" (full 12-row state) or "omega2"/"omega1" (reduced_planar.hpp)
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

// ---------------------------------------------------------------- signals
// SIGINT and SIGTERM set a flag (nothing else happens in the handler); the
// run loop asks `stop_signal()` at every step boundary, writes a checkpoint
// and stops. A second signal of the same kind kills at once (SA_RESETHAND).
void install_stop_signal_handlers();
int stop_signal();  // 0, or the number of the first SIGINT/SIGTERM received
void clear_stop_signal();  // for tests

// Thrown by the checkpoint hook after it saved the run because of a signal.
struct Interrupted : Error {
  Interrupted(const std::string& message, int signal_number) : Error(message), signal(signal_number) {}
  int signal;
};

// When to write a checkpoint: every `interval_s` wall seconds (0: never on a
// timer) and whenever a stop signal arrived.
class CheckpointSchedule {
 public:
  explicit CheckpointSchedule(double interval_s);
  bool due() const;
  void written();  // restart the timer
 private:
  double interval_s_;
  std::chrono::steady_clock::time_point last_;
};

}  // namespace rodcore
