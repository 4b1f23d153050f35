// A one-line progress bar on stderr, shown only when stderr is a terminal
// (so logs and pipes stay clean).
#pragma once
#include <chrono>
#include <cstdio>
#include <functional>
#include <optional>
#include <string>

#include "rodcore/observer.hpp"

namespace rodcore {

class ProgressBar {
 public:
  // time_unit_ps > 0: the bar also shows the simulated time per wall hour, in ns/h
  // (rod time t in units of time_unit_ps; from the first t it was shown, so a resumed run
  // reports its own pace).
  explicit ProgressBar(bool enabled, std::FILE* out = stderr, double time_unit_ps = 0.0);
  ~ProgressBar();
  // Redraws at most 10 times a second; `note` (e.g. the kinetic temperature)
  // is asked for only when it does.
  void update(double t, double t_end, const std::function<std::string()>& note = {});
  void finish();  // erases the bar
  static bool stderr_is_terminal();

 private:
  bool enabled_;
  bool drawn_ = false;
  std::FILE* out_;
  double time_unit_ps_;
  std::optional<double> t_first_;
  std::chrono::steady_clock::time_point start_, last_;
};

// The bar as an observer of a run: redrawn after every step; a thermal scene
// also shows the kinetic temperature 2 KE / (6 N) of its last frame against kT.
class ProgressObserver : public Observer {
 public:
  explicit ProgressObserver(ProgressBar& bar) : bar_(bar) {}
  void frame(const Simulation& sim, const Frame& frame) override;
  void stepped(const Simulation& sim) override;

 private:
  ProgressBar& bar_;
  std::optional<double> kinetic_kT_;
};

}  // namespace rodcore
