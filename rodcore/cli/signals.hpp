// Process signals for rodsim (not part of the library: a library must not
// take over a process's signal handlers). SIGINT and SIGTERM set a flag
// (nothing else happens in the handler); rodsim's CheckpointWriter
// (rodcore/checkpoint.hpp) asks CheckpointSchedule::due() at every step
// boundary, writes a checkpoint and stops with Interrupted. A second signal
// of the same kind kills at once (SA_RESETHAND). docs/reliability.md.
#pragma once
#include <chrono>
#include <csignal>
#include <string>

#include "rodcore/error.hpp"

namespace rodcore {

void install_stop_signal_handlers();
int stop_signal();         // 0, or the number of the first SIGINT/SIGTERM received
void clear_stop_signal();  // for tests

// Thrown after the run was saved because of a signal.
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
