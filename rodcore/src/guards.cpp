#include "rodcore/guards.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "rodcore/diagnostics.hpp"
#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"

namespace rodcore {

namespace {

std::string num(double x) { return message_number(x); }

const char* kComponentNames[12] = {"gamma1", "gamma2", "gamma3", "omega1", "omega2", "omega3",
                                   "Gamma1", "Gamma2", "Gamma3", "Omega1", "Omega2", "Omega3"};

struct NonFiniteGuard : Observer {
  std::string source;
  std::vector<double> s;
  void step(const Simulation&, const StepView& v) override {
    const long bad = first_non_finite(v.y, v.n);
    if (bad < 0) return;
    std::string where = "the s = 0 frame";
    if (static_cast<std::size_t>(bad) < v.rows->size() * v.N) {
      const std::size_t k = static_cast<std::size_t>(bad) / v.N, i = static_cast<std::size_t>(bad) % v.N;
      where = std::string(kComponentNames[(*v.rows)[k]]) + " at s = " + num(s[i]);
    }
    throw NumericalError(source + ": non-finite value (NaN/Inf) in " + where + ", t = " + num(v.t) +
                         ". The run blew up: reduce solver.dt or tolerances, raise "
                         "rod.points, or check the initial fields.");
  }
};

struct FoldGuard : Observer {
  std::string source;
  std::vector<double> s;
  void step(const Simulation&, const StepView& v) override {
    // Gamma3 is integrated in both systems (row k3 of the integrated state).
    const auto& rows = *v.rows;
    const std::size_t k3 = static_cast<std::size_t>(std::find(rows.begin(), rows.end(), 8) - rows.begin());
    const double* G3row = v.y + k3 * v.N;
    const std::size_t i = static_cast<std::size_t>(std::min_element(G3row, G3row + v.N) - G3row);
    const double G3 = G3row[i];
    if (G3 <= 0.0)
      throw NumericalError(source + ": the rod folded (Gamma3 = " + num(G3) + " <= 0) at s = " + num(s[i]) +
                           ", t = " + num(v.t) +
                           ". The deformation is too large for the model: lower the amplitude, "
                           "or set checks.stop_on_fold = false to continue anyway.");
  }
};

struct EnergyGuard : Observer {
  std::string source;
  double max_drift;
  void frame(const Simulation&, const Frame& f) override {
    if (!f.checked_energy) return;
    const double E = *f.checked_energy, drift = *f.energy_drift;
    if (!std::isfinite(E))
      throw NumericalError(source + ": the energy is not finite (E = " + num(E) + ") at t = " + num(f.t) +
                           (f.index == 0
                                ? ": the initial fields are so large that their squares overflow; check "
                                  "the initial fields and their units (dimensionless, paper Sec 2.2)"
                                : ": the run blew up; reduce solver.dt or tolerances, or raise rod.points"));
    if (!(drift <= max_drift))
      throw NumericalError(source + ": relative energy drift " + num(drift) + " at t = " + num(f.t) +
                           " exceeds checks.max_energy_drift = " + num(max_drift) +
                           "; tighten solver.rtol/atol, reduce dt, or raise rod.points");
  }
};

struct DirectorGuard : Observer {
  std::string source;
  double max_error;
  void frame(const Simulation&, const Frame& f) override {
    if (!f.end_rotation) return;  // no reconstruction at this frame
    if (f.max_director_norm_error > max_error)
      throw NumericalError(source + ": director norm error " + num(f.max_director_norm_error) + " at t = " +
                           num(f.t) + " exceeds checks.max_director_norm_error = " + num(max_error) +
                           ". Directors are unit quaternions, exact to round-off (~1e-15): a larger error "
                           "means non-finite or huge curvatures Omega; check the fields, or raise the bound "
                           "if it is below round-off");
  }
};

}  // namespace

std::vector<std::unique_ptr<Observer>> make_guards(const Scene& sc, const std::vector<double>& s) {
  std::vector<std::unique_ptr<Observer>> out;
  auto nf = std::make_unique<NonFiniteGuard>();
  nf->source = sc.source;
  nf->s = s;
  out.push_back(std::move(nf));
  if (sc.checks.stop_on_fold) {
    auto fold = std::make_unique<FoldGuard>();
    fold->source = sc.source;
    fold->s = s;
    out.push_back(std::move(fold));
  }
  auto e = std::make_unique<EnergyGuard>();
  e->source = sc.source;
  e->max_drift = sc.checks.max_energy_drift;
  out.push_back(std::move(e));
  auto dg = std::make_unique<DirectorGuard>();
  dg->source = sc.source;
  dg->max_error = sc.checks.max_director_norm_error;
  out.push_back(std::move(dg));
  return out;
}

std::pair<std::string, std::string> thermal_settings_problem(const Scene& sc) {
  const Thermal& t = sc.thermal;
  const bool langevin =
      sc.solver.time == TimeMethod::langevin || (sc.solver.time == TimeMethod::automatic && t.has_friction());
  if (t.on) {
    if (!(t.kT >= 0.0) || !std::isfinite(t.kT))
      return {"thermal.kT", "found " + num(t.kT) + "; allowed: a number >= 0 (finite)"};
    for (double z : {t.friction_translational[0], t.friction_translational[1], t.friction_rotational[0],
                     t.friction_rotational[1]})
      if (!(z >= 0.0) || !std::isfinite(z))
        return {"thermal.friction_translational",
                "the frictions must be numbers >= 0 (finite); found " + num(z)};
  }
  if (sc.solver.time == TimeMethod::langevin && !t.on)
    return {"solver.time",
            "\"langevin\" is the Langevin rod of a [thermal] section: add [thermal] with kT or "
            "temperature_K and the frictions (docs/thermal.md)"};
  const bool brownian = sc.solver.time == TimeMethod::brownian;
  if (brownian) {
    if (!t.on)
      return {"solver.time",
              "\"brownian\" is the overdamped rod of a [thermal] section: add [thermal] with kT or "
              "temperature_K and the frictions (docs/thermal.md)"};
    for (double z : {t.friction_translational[0], t.friction_translational[1], t.friction_rotational[0],
                     t.friction_rotational[1]})
      if (!(z > 0.0))
        return {"thermal.friction_translational",
                "\"brownian\" moves the rod by its friction: every friction (translational and rotational, "
                "along and across) must be > 0, e.g. \"water\"; found " +
                    num(z)};
    if (sc.solver.space == SpaceMethod::spectral)
      return {"solver.space",
              "\"brownian\" solves a banded system and needs a local d/ds: \"fd4\" or \"auto\""};
  }
  if (t.on && t.has_friction() && !langevin && !brownian)
    return {"solver.time", std::string("\"")
                               .append(to_string(sc.solver.time))
                               .append("\" cannot carry the friction and noise of [thermal] "
                                       "(thermal.friction_translational / friction_rotational > 0); use "
                                       "\"langevin\" or \"auto\" (with no friction a thermal sample runs "
                                       "with any integrator)")};
  if ((langevin || brownian) && std::isfinite(sc.checks.max_energy_drift))
    return {"checks.max_energy_drift",
            "the Langevin rod exchanges energy with its bath, so its energy is not conserved; remove "
            "checks.max_energy_drift from this scene"};
  if ((langevin || brownian) && sc.output.frames > 1 && sc.output.t_end > 0.0) {
    const double interval = sc.output.t_end / static_cast<double>(sc.output.frames - 1);
    const double n = interval / sc.solver.dt;
    if (!(std::round(n) >= 1.0) || std::abs(n - std::round(n)) > 1e-9 * n)
      return {"solver.dt",
              std::string(brownian ? "the overdamped rod" : "the Langevin rod") +
                  " steps with a fixed solver.dt = " + num(sc.solver.dt) +
                  ", which must divide the output interval output.t_end / (output.frames - 1) = " +
                  message_number(interval, 12) +
                  " (every frame is a step's state, never an interpolation); e.g. solver.dt = " +
                  message_number(interval / std::max(1.0, std::ceil(n)), 12)};
  }
  return {};
}

void validate_run_settings(const Scene& sc) {
  if (sc.rod.points <= 0 || !(sc.rod.length > 0.0) || !std::isfinite(sc.rod.length))
    throw InputError(sc.source + ": rod.points and rod.length must be positive (got points = " +
                     std::to_string(sc.rod.points) + ", length = " + num(sc.rod.length) + ")");
  if (sc.output.frames < 1) throw InputError(sc.source + ": output.frames must be >= 1");
  if (!(sc.output.t_end >= 0.0) || !std::isfinite(sc.output.t_end))
    throw InputError(sc.source + ": output.t_end must be >= 0 and finite");
  // A scene built in code may hold an enum value cast from a bad integer.
  for (const std::string& bad :
       {invalid_choice("solver.space", sc.solver.space), invalid_choice("solver.time", sc.solver.time),
        invalid_choice("solver.reduce", sc.solver.reduce), invalid_choice("initial.kind", sc.initial.kind)})
    if (!bad.empty()) throw InputError(sc.source + ": " + bad);
  if (const auto [key, problem] = thermal_settings_problem(sc); !key.empty())
    throw InputError(sc.source + ": " + key + ": " + problem);
}

void check_initial_finite(const Scene& sc, const std::vector<double>& y, const std::vector<double>& s) {
  const std::size_t N = s.size();
  if (long bad = first_non_finite(y.data(), y.size()); bad >= 0) {
    const std::size_t r = static_cast<std::size_t>(bad) / N, i = static_cast<std::size_t>(bad) % N;
    throw InputError(sc.source + ": initial field " + kComponentNames[r] + " is not finite (" + num(y[bad]) +
                     ") at point " + std::to_string(i) + " (s = " + num(s[i]) + ")");
  }
}

}  // namespace rodcore
