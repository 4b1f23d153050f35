// Time integrators for dy/dt = f(t, y), behind one interface (method of
// lines, paper Sec 5.1). All of them give a continuous extension ("dense
// output") on the last step, so output times never shorten steps:
//   "rk4"          classic RK4, fixed step dt (the paper's scheme); only the
//                  last step to t_stop may be shortened. Dense output: cubic
//                  Hermite from y, f at both ends (f at the new point is the
//                  next step's first stage, so it costs nothing).
//   "rk4-doubling" RK4 with step-doubling error control and local
//                  extrapolation (Numerical Recipes Sec 16.2 style, the paper's
//                  "time-step control"), Hermite dense output.
//   "dopri5"       Dormand-Prince 5(4), FSAL, Hairer's PI step control and
//                  4th-order continuous extension (Shampine 1986, as in
//                  Hairer's dopri5.f).
//   "dop853"       Dormand-Prince 8(5,3) with Hairer's error estimator and
//                  7th-order dense output (3 extra stages per output step).
//   "langevin"     the Langevin splitting of the thermal rod (docs/thermal.md):
//                  per step the system's `bath`, the exact Ornstein-Uhlenbeck
//                  step over dt (friction and noise), then one classic RK4 step of
//                  f (the conservative rod) -- the Strang splitting O(dt/2)
//                  H(dt) O(dt/2) with consecutive half steps merged; fixed
//                  step dt. Dense output: the cubic Hermite of the H part.
//   "brownian"     the overdamped rod (brownian.hpp): per step the system's
//                  `bath`, the overdamped step over dt on y, in place; fixed step dt.
//                  Dense output: linear between the step's ends.
// Tableaux: Hairer, Norsett & Wanner, Solving ODEs I (2nd ed. 1993), II.5 and
// II.10. Error norm (all adaptive schemes): RMS over components of
// err_i / (atol + rtol max(|y_i(t)|, |y_i(t+h)|)).
#pragma once
#include <cstddef>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "rodcore/run_point.hpp"  // IntegratorState
#include "rodcore/scene.hpp"      // TimeMethod

namespace rodcore {

struct OdeSystem {
  std::size_t n = 0;
  std::function<void(double t, const double* y, double* dydt)> f;
  // Friction and noise over dt on y, in place (force.hpp, Bath), for the
  // stochastic schemes: "langevin" composes it with an RK4 step of f,
  // "brownian" takes it as its whole step. `step` is the index of the step
  // (the random numbers' counter).
  std::function<void(long step, double* y)> bath;
  // Optional, every integrator: called on the state y at the end of every
  // accepted step [t_prev, t], before the slope there is formed; may move y
  // back onto a manifold the semi-discrete flow leaves (closure.hpp).
  // Returns whether it changed y.
  std::function<bool(double t_prev, double t, double* y)> project;
};

struct IntegratorOptions {
  double rtol = 1e-10;
  double atol = 1e-10;
  double dt = 1e-2;       // fixed step (rk4) or first trial step (adaptive)
  double dt_min = 1e-12;  // adaptive step below this -> NumericalError
  double dt_max = std::numeric_limits<double>::infinity();
  long max_steps = 100000000;
  // Number of components the RMS error norm averages over; 0: the system
  // size n. A reduced system whose left-out components are identically zero
  // sets the full size, so that it takes exactly the steps of the full one.
  std::size_t norm_size = 0;
};

// The stability limit of an explicit fixed step on the imaginary axis, where
// the spectrum of the rod linearised about its rest state lies: |lambda dt| <=
// bound (infinity: no limit, an adaptive or an implicit scheme). `scheme`
// names the scheme that sets it and `otherwise` what a user can do besides a
// shorter dt, for the message of the check (stability.hpp, check_step_limit).
struct StepLimit {
  double bound = std::numeric_limits<double>::infinity();
  std::string scheme;
  std::string otherwise;
};

class TimeIntegrator {
 public:
  TimeIntegrator(OdeSystem system, IntegratorOptions options);
  virtual ~TimeIntegrator() = default;
  TimeIntegrator(const TimeIntegrator&) = delete;
  TimeIntegrator& operator=(const TimeIntegrator&) = delete;

  virtual std::string name() const = 0;
  virtual bool adaptive() const = 0;
  virtual int order() const = 0;

  // Start from (t0, y0); evaluates f(t0, y0).
  void reset(double t0, const double* y0);
  // Snapshot / restore at a step boundary (instead of reset()). restore_state
  // throws InputError if the sizes do not match this system.
  IntegratorState save_state() const;
  void restore_state(const IntegratorState& state);
  // Take one accepted step, never past t_stop. Throws NumericalError on step
  // underflow (adaptive), too many steps, or non-finite numbers in the step.
  virtual void step(double t_stop) = 0;
  // The solution at t in [t_prev(), t()] from the last step's continuous
  // extension; `out` holds n values.
  virtual void dense(double t, double* out) const = 0;

  double t() const { return t_; }
  double t_prev() const { return t_prev_; }
  double dt_next() const { return h_; }
  const std::vector<double>& y() const { return y_; }
  std::size_t size() const { return sys_.n; }
  long steps() const { return steps_; }
  long rejected() const { return rejected_; }
  long rhs_evaluations() const { return rhs_evals_; }

 protected:
  void eval(double t, const double* y, double* f) {
    ++rhs_evals_;
    sys_.f(t, y, f);
  }
  // Clamp the trial step to t_stop; returns true if this step ends at t_stop.
  bool clamp(double& h, double t_stop) const;
  void check_steps() const;
  // Controller memory beyond dt_next (e.g. the PI controller's last error).
  virtual std::vector<double> controller_memory() const { return {}; }
  virtual void set_controller_memory(const std::vector<double>&) {}
  // One classic RK4 step of size h from (t, y0) with f0 = f(t, y0) given,
  // into y1 (not y0): the stage arithmetic of rk4, rk4-doubling and langevin.
  void rk4_step(double t, const double* y0, const double* f0, double h, double* y1);
  // sys_.project on y_ at the end of an accepted step (t_prev_, t_ set).
  bool project_end() { return sys_.project && sys_.project(t_prev_, t_, y_.data()); }
  // Called at the end of reset() and restore_state().
  virtual void restarted() {}
  // Cubic Hermite interpolation on [t_prev, t] from y, f at both ends.
  void hermite(double t, double* out) const;

  OdeSystem sys_;
  IntegratorOptions opt_;
  std::vector<double> y_, f_;            // at t_
  std::vector<double> y_prev_, f_prev_;  // at t_prev_
  double t_ = 0.0, t_prev_ = 0.0, h_ = 0.0;
  std::vector<double> rk_k2_, rk_k3_, rk_k4_, rk_tmp_;  // rk4_step's stages
  long steps_ = 0, rejected_ = 0, rhs_evals_ = 0;
};

// The stability limit of scheme `kind` (none for the adaptive and the implicit
// ones), known before its integrator is made: a scene's step is checked first.
StepLimit step_limit(TimeMethod kind);

// kind = rk4 | rk4_doubling | dopri5 | dop853 | langevin | brownian (both need
// system.bath); throws InputError otherwise
// (automatic is resolved by Simulation before).
std::unique_ptr<TimeIntegrator> make_time_integrator(TimeMethod kind, OdeSystem system,
                                                     const IntegratorOptions& options);

}  // namespace rodcore
