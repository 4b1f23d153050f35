// A one-line progress bar on stderr, shown only when stderr is a terminal
// (so logs and pipes stay clean).
#pragma once
#include <chrono>
#include <cstdio>

#include "rodcore/observer.hpp"

namespace rodcore {

class ProgressBar {
 public:
  explicit ProgressBar(bool enabled, std::FILE* out = stderr);
  ~ProgressBar();
  void update(double t, double t_end);  // redraws at most 10 times a second
  void finish();                        // erases the bar
  static bool stderr_is_terminal();

 private:
  bool enabled_;
  bool drawn_ = false;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_, last_;
};

// The bar as an observer of a run: redrawn after every step.
class ProgressObserver : public Observer {
 public:
  explicit ProgressObserver(ProgressBar& bar) : bar_(bar) {}
  void stepped(const Simulation& sim) override;

 private:
  ProgressBar& bar_;
};

}  // namespace rodcore
