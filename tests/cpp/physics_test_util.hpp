// Small helpers shared by the physics/numerics GoogleTest suites.
#pragma once
#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

#include "rodcore/scene.hpp"
#include "rodcore/simulation.hpp"

namespace rodtest {

inline constexpr double kPi = std::numbers::pi;

// A straight twisted rod with the paper's Sec 3.1 / Fig 3 parameters:
// Gamma03 = Omega03 = 1, k = 2 (L = pi, mode 1).
inline rodcore::Scene twisted_wave_scene(int N, const std::string& kappa, const std::string& branch,
                                         double A = 0.5) {
  rodcore::Scene sc;
  sc.source = "<test>";
  sc.rod.length = kPi;
  sc.rod.points = N;
  sc.rod.Gamma0 = {0.0, 0.0, 1.0};
  sc.rod.Omega0 = {0.0, 0.0, 1.0};
  sc.initial.kind = rodcore::InitialKind::twisted_wave;
  sc.initial.numbers = {{"mode", 1.0}, {"A", A}};
  sc.initial.strings = {{"kappa", kappa}, {"branch", branch}};
  return sc;
}

// Run a scene, returning the states of all frames (12 N each).
struct RunResult {
  std::vector<double> t;
  std::vector<std::vector<double>> y;
  std::vector<double> energy;
  std::vector<std::vector<double>> centerline, directors;
  std::vector<double> norm_error;
  rodcore::RunSummary summary;
};

inline RunResult run_scene(const rodcore::Scene& sc) {
  RunResult r;
  rodcore::Simulation sim(sc);
  sim.add_observer(rodcore::on_frame([&](const rodcore::Frame& f) {
    r.t.push_back(f.t);
    r.y.emplace_back(f.y, f.y + 12 * f.N);
    if (f.energy) r.energy.push_back(*f.energy);
    if (f.centerline) r.centerline.emplace_back(f.centerline, f.centerline + 3 * f.N);
    if (f.directors) r.directors.emplace_back(f.directors, f.directors + 9 * f.N);
    r.norm_error.push_back(f.max_director_norm_error);
  }));
  r.summary = sim.run();
  return r;
}

inline double max_abs_diff(const std::vector<double>& a, const std::vector<double>& b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

}  // namespace rodtest
