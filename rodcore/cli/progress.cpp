#include "progress.hpp"

#include <unistd.h>

#include <algorithm>
#include <string>

#include "rodcore/simulation.hpp"

namespace rodcore {

ProgressBar::ProgressBar(bool enabled, std::FILE* out, double time_unit_ps)
    : enabled_(enabled),
      out_(out),
      time_unit_ps_(time_unit_ps),
      start_(std::chrono::steady_clock::now()),
      last_(start_) {}

ProgressBar::~ProgressBar() { finish(); }

bool ProgressBar::stderr_is_terminal() { return isatty(STDERR_FILENO) == 1; }

void ProgressBar::update(double t, double t_end, const std::function<std::string()>& note) {
  if (!enabled_) return;
  auto now = std::chrono::steady_clock::now();
  if (!t_first_) t_first_ = t;
  if (drawn_ && now - last_ < std::chrono::milliseconds(100) && t < t_end) return;
  last_ = now;
  double f = t_end > 0 ? std::clamp(t / t_end, 0.0, 1.0) : 1.0;
  double elapsed = std::chrono::duration<double>(now - start_).count();
  const int width = 30;
  int filled = static_cast<int>(f * width);
  std::string bar(filled, '#');
  bar.append(width - filled, '.');
  char eta[32] = "";
  if (f > 0.0 && f < 1.0) std::snprintf(eta, sizeof eta, "  ETA %.0f s", elapsed * (1.0 - f) / f);
  char pace[40] = "";
  if (time_unit_ps_ > 0.0 && elapsed > 1.0)  // simulated ns per wall hour
    std::snprintf(pace, sizeof pace, "  %.3g ns/h",
                  (t - *t_first_) * time_unit_ps_ * 1e-3 * 3600.0 / elapsed);
  const std::string extra = note ? "  " + note() : std::string();
  std::fprintf(out_, "\r[%s] %5.1f%%  t = %.4g / %.4g%s%s%s   ", bar.c_str(), 100.0 * f, t, t_end, pace,
               extra.c_str(), eta);
  std::fflush(out_);
  drawn_ = true;
}

void ProgressBar::finish() {
  if (!enabled_ || !drawn_) return;
  std::fprintf(out_, "\r%*s\r", 80, "");
  std::fflush(out_);
  drawn_ = false;
}

void ProgressObserver::frame(const Simulation&, const Frame& f) {
  if (f.kinetic_kT) kinetic_kT_ = *f.kinetic_kT;
}

void ProgressObserver::stepped(const Simulation& sim) {
  const Thermal& th = sim.scene().thermal;
  // the overdamped rod has no velocities: its kinetic temperature is no news
  if (!kinetic_kT_ || sim.scene().solver.time == TimeMethod::brownian) {
    bar_.update(sim.integrator_time(), sim.scene().output.t_end);
    return;
  }
  bar_.update(sim.integrator_time(), sim.scene().output.t_end, [&] {
    char text[80];
    std::snprintf(text, sizeof text, "kinetic kT %.4g at the last frame (kT %.4g)", *kinetic_kT_, th.kT);
    return std::string(text);
  });
}

}  // namespace rodcore
