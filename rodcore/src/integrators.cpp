#include "rodcore/integrators.hpp"

#include <algorithm>
#include <cmath>

#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"

namespace rodcore {
namespace {
#include "dop853_tableau.inc"

// RMS norm of err_i / (atol + rtol max(|y0_i|, |y1_i|)).
double error_norm(const std::vector<double>& err, const std::vector<double>& y0,
                  const std::vector<double>& y1, double atol, double rtol, std::size_t norm_size) {
  double sum = 0.0;
  const std::size_t n = err.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double sk = atol + rtol * std::max(std::abs(y0[i]), std::abs(y1[i]));
    const double e = err[i] / sk;
    sum += e * e;
  }
  return std::sqrt(sum / static_cast<double>(norm_size > 0 ? norm_size : n));
}

[[noreturn]] void non_finite(const std::string& method, double t, double h) {
  throw NumericalError(method + ": non-finite numbers (NaN/Inf) in a step at t = " + message_number(t) +
                       " (dt = " + message_number(h) +
                       "). The state blew up: check the initial fields, reduce dt or rtol/atol, "
                       "or increase rod.points.");
}

// Classic RK4 is stable on the imaginary axis up to |lambda dt| = 2 sqrt 2 ~
// 2.83; we allow 2.8 (1 % margin).
constexpr double kRK4ImaginaryBound = 2.8;

// ---------------------------------------------------------------- RK4
class RK4 final : public TimeIntegrator {
 public:
  RK4(OdeSystem s, IntegratorOptions o) : TimeIntegrator(std::move(s), o) { h_ = opt_.dt; }
  std::string name() const override { return "rk4"; }
  bool adaptive() const override { return false; }
  int order() const override { return 4; }

  void step(double t_stop) override {
    check_steps();
    double h = opt_.dt;
    clamp(h, t_stop);
    rk4_step(t_, y_.data(), f_.data(), h, y_prev_.data());
    y_prev_.swap(y_);
    f_prev_.swap(f_);
    t_prev_ = t_;
    t_ = (t_stop - (t_ + h) <= 0.0) ? t_stop : t_ + h;
    ++steps_;
    project_end();
    eval(t_, y_.data(), f_.data());  // first stage of the next step and Hermite slope
  }
  void dense(double t, double* out) const override { hermite(t, out); }
};

// -------------------------------------------------------- Langevin
// One step: the exact OU step over dt, then one RK4 step of the conservative
// rod. This is the Strang splitting O(dt/2) H(dt) O(dt/2) with the trailing
// and leading half steps of consecutive steps merged (two exact OU steps of
// dt/2 compose to one of dt), observed after H instead of between the half
// steps: the same chain of operations, one noise draw per step instead of two
// (docs/thermal.md). The step index counts from the start of the run
// (restored with the checkpoint), so the random numbers of every step are
// those of an uninterrupted run.
class Langevin final : public TimeIntegrator {
 public:
  Langevin(OdeSystem s, IntegratorOptions o) : TimeIntegrator(std::move(s), o) {
    if (!sys_.bath) throw InputError("solver.time = \"langevin\": the system has no friction-and-noise step");
    ya_.resize(sys_.n);
    fb_.resize(sys_.n);
    h_ = opt_.dt;
  }
  std::string name() const override { return "langevin"; }
  bool adaptive() const override { return false; }
  int order() const override { return 2; }  // weak order of the splitting; the H part is RK4

  // Never shortened: the OU coefficients are those of dt (the scene makes
  // output times multiples of dt; other times are dense output).
  void step(double) override {
    check_steps();
    const double h = opt_.dt;
    ya_ = y_;
    sys_.bath(steps_, ya_.data());
    eval(t_, ya_.data(), f_.data());  // k1, the Hermite slope at the start of H
    y_prev_.swap(y_);
    rk4_step(t_, ya_.data(), f_.data(), h, y_.data());
    t_prev_ = t_;
    ++steps_;
    t_ = origin_ + static_cast<double>(steps_) * h;  // not accumulated: frame times stay on steps
    project_end();
    fb_ready_ = false;
  }

  void dense(double t, double* out) const override {
    const double h = t_ - t_prev_;
    // Step ends (to rounding of the frame times): the states of the chain.
    if (h <= 0.0 || std::abs(t - t_) <= 1e-9 * h) {
      std::copy(y_.begin(), y_.end(), out);
      return;
    }
    if (std::abs(t - t_prev_) <= 1e-9 * h) {
      std::copy(y_prev_.begin(), y_prev_.end(), out);
      return;
    }
    if (!fb_ready_) {  // f at the end of H: only for steps that hold an output time
      auto* self = const_cast<Langevin*>(this);
      self->eval(t_, y_.data(), self->fb_.data());
      self->fb_ready_ = true;
    }
    const double th = (t - t_prev_) / h;  // between the OU kick and the end: the H part's Hermite cubic
    for (std::size_t i = 0; i < sys_.n; ++i) {
      const double y0 = ya_[i], y1 = y_[i];
      out[i] = (1.0 - th) * y0 + th * y1 +
               th * (th - 1.0) * ((1.0 - 2.0 * th) * (y1 - y0) + (th - 1.0) * h * f_[i] + th * h * fb_[i]);
    }
  }

 private:
  void restarted() override { origin_ = t_ - static_cast<double>(steps_) * opt_.dt; }
  std::vector<double> ya_, fb_;  // ya_: after the OU kick (the start of H)
  bool fb_ready_ = false;
  double origin_ = 0.0;  // the time of step 0
};

// ---------------------------------------------------- RK4 step doubling
class RK4Doubling final : public TimeIntegrator {
 public:
  RK4Doubling(OdeSystem s, IntegratorOptions o) : TimeIntegrator(std::move(s), o) {
    const std::size_t n = sys_.n;
    k1_.resize(n);
    ybig_.resize(n);
    yhalf_.resize(n);
    ysmall_.resize(n);
    err_.resize(n);
    h_ = opt_.dt;
  }
  std::string name() const override { return "rk4-doubling"; }
  bool adaptive() const override { return true; }
  int order() const override { return 4; }

  void step(double t_stop) override {
    constexpr double safety = 0.9, grow = -0.2, shrink = -0.25, errcon = 1.89e-4;
    const std::size_t n = sys_.n;
    for (;;) {
      check_steps();
      double h = std::min(h_, opt_.dt_max);
      const bool last = clamp(h, t_stop);
      if (!last && h < opt_.dt_min) underflow(h);
      // one big step, two half steps (the first half step shares f(t, y))
      rk4_step(t_, y_.data(), f_.data(), h, ybig_.data());
      rk4_step(t_, y_.data(), f_.data(), 0.5 * h, yhalf_.data());
      eval(t_ + 0.5 * h, yhalf_.data(), k1_.data());
      rk4_step(t_ + 0.5 * h, yhalf_.data(), k1_.data(), 0.5 * h, ysmall_.data());
      for (std::size_t i = 0; i < n; ++i) err_[i] = ysmall_[i] - ybig_[i];
      const double err = error_norm(err_, y_, ysmall_, opt_.atol, opt_.rtol, opt_.norm_size);
      if (!std::isfinite(err)) non_finite(name(), t_, h);
      if (err <= 1.0) {
        y_prev_.swap(y_);
        f_prev_.swap(f_);
        // local extrapolation: 5th-order accurate
        for (std::size_t i = 0; i < n; ++i) y_[i] = ysmall_[i] + err_[i] / 15.0;
        t_prev_ = t_;
        t_ = last ? t_stop : t_ + h;
        ++steps_;
        project_end();
        eval(t_, y_.data(), f_.data());
        const double proposal = err > errcon ? safety * h * std::pow(err, grow) : 5.0 * h;
        if (!last || proposal > h_) h_ = proposal;
        return;
      }
      ++rejected_;
      h_ = std::max(safety * h * std::pow(err, shrink), 0.1 * h);
    }
  }
  void dense(double t, double* out) const override { hermite(t, out); }

 private:
  [[noreturn]] void underflow(double h) const {
    throw NumericalError(name() + ": step size underflow at t = " + message_number(t_) +
                         " (dt = " + message_number(h) + " < solver.dt_min = " + message_number(opt_.dt_min) +
                         "). The solution is not smooth enough to resolve: increase rod.points, "
                         "loosen rtol/atol, or look for a blow-up in the initial fields.");
  }
  std::vector<double> k1_, ybig_, yhalf_, ysmall_, err_;
};

// ------------------------------------------------ embedded pairs (Hairer)
// Shared step-size control of dopri5.f / dop853.f: PI controller with
// exponent `expo`, memory `beta`, bounds 1/fac2 <= h_new / h <= 1/fac1.
class Embedded : public TimeIntegrator {
 public:
  Embedded(OdeSystem s, IntegratorOptions o, int stages, double expo, double beta, double fac1, double fac2)
      : TimeIntegrator(std::move(s), o), expo_(expo), beta_(beta), fac1_(fac1), fac2_(fac2) {
    k_.assign(stages, std::vector<double>(sys_.n));
    tmp_.resize(sys_.n);
    ynew_.resize(sys_.n);
    h_ = opt_.dt;
  }
  bool adaptive() const override { return true; }

  void step(double t_stop) override {
    constexpr double safe = 0.9;
    bool rejected_before = false;
    for (;;) {
      check_steps();
      double h = std::min(h_, opt_.dt_max);
      const bool last = clamp(h, t_stop);
      if (!last && h < opt_.dt_min)
        throw NumericalError(name() + ": step size underflow at t = " + message_number(t_) + " (dt = " +
                             message_number(h) + " < solver.dt_min = " + message_number(opt_.dt_min) +
                             "). The solution is not smooth enough to resolve: increase "
                             "rod.points, loosen rtol/atol, or look for a blow-up.");
      const double err = attempt(h);
      if (!std::isfinite(err)) non_finite(name(), t_, h);
      const double fac11 = std::pow(err, expo_);
      if (err <= 1.0) {
        double fac = fac11 / std::pow(facold_, beta_);
        fac = std::max(1.0 / fac2_, std::min(1.0 / fac1_, fac / safe));
        double hnew = h / fac;
        if (rejected_before) hnew = std::min(hnew, h);
        facold_ = std::max(err, 1e-4);
        accept(h, last ? t_stop : t_ + h);
        ++steps_;
        if (project_end()) eval(t_, y_.data(), f_.data());  // the FSAL slope is the unprojected state's
        if (!last || hnew > h_) h_ = hnew;
        return;
      }
      ++rejected_;
      rejected_before = true;
      h_ = h / std::min(1.0 / fac1_, fac11 / safe);
    }
  }

 protected:
  // Compute stages and ynew_ for step h from (t_, y_); return the error norm.
  virtual double attempt(double h) = 0;
  // Called after acceptance: prepare dense output, then move to the new point.
  virtual void accept(double h, double t_new) = 0;

  // tmp_ = y_ + h sum_j a[j] k_j over j < s
  void combine(const double* a, int s, double h) {
    const std::size_t n = sys_.n;
    std::copy(y_.begin(), y_.end(), tmp_.begin());
    for (int j = 0; j < s; ++j) {
      if (a[j] == 0.0) continue;
      const double c = h * a[j];
      const double* kj = k_[j].data();
      for (std::size_t i = 0; i < n; ++i) tmp_[i] += c * kj[i];
    }
  }

  std::vector<double> controller_memory() const override { return {facold_}; }
  void set_controller_memory(const std::vector<double>& m) override {
    if (m.size() != 1) throw InputError(name() + ": controller memory must hold 1 value");
    facold_ = m[0];
  }

  std::vector<std::vector<double>> k_;
  std::vector<double> tmp_, ynew_;
  double expo_, beta_, fac1_, fac2_;
  double facold_ = 1e-4;
};

// ----------------------------------------------------------- DOPRI5
class Dopri5 final : public Embedded {
 public:
  Dopri5(OdeSystem s, IntegratorOptions o)
      : Embedded(std::move(s), o, 7, 0.2 - 0.04 * 0.75, 0.04, 0.2, 10.0) {
    const std::size_t n = sys_.n;
    for (auto& r : rcont_) r.resize(n);
    err_.resize(n);
  }
  std::string name() const override { return "dopri5"; }
  int order() const override { return 5; }

  double attempt(double h) override {
    static constexpr double c[7] = {0.0, 0.2, 0.3, 0.8, 8.0 / 9.0, 1.0, 1.0};
    static constexpr double a[7][6] = {
        {0, 0, 0, 0, 0, 0},
        {1.0 / 5.0, 0, 0, 0, 0, 0},
        {3.0 / 40.0, 9.0 / 40.0, 0, 0, 0, 0},
        {44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0, 0, 0, 0},
        {19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0, 0, 0},
        {9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0, 0},
        {35.0 / 384.0, 0.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0}};
    static constexpr double e[7] = {71.0 / 57600.0,      0.0,          -71.0 / 16695.0, 71.0 / 1920.0,
                                    -17253.0 / 339200.0, 22.0 / 525.0, -1.0 / 40.0};
    const std::size_t n = sys_.n;
    std::copy(f_.begin(), f_.end(), k_[0].begin());  // FSAL
    for (int s = 1; s < 6; ++s) {
      combine(a[s], s, h);
      eval(t_ + c[s] * h, tmp_.data(), k_[s].data());
    }
    combine(a[6], 6, h);
    std::copy(tmp_.begin(), tmp_.end(), ynew_.begin());
    eval(t_ + h, ynew_.data(), k_[6].data());
    for (std::size_t i = 0; i < n; ++i) {
      double s = 0.0;
      for (int j = 0; j < 7; ++j) s += e[j] * k_[j][i];
      err_[i] = h * s;
    }
    return error_norm(err_, y_, ynew_, opt_.atol, opt_.rtol, opt_.norm_size);
  }

  void accept(double h, double t_new) override {
    // Shampine's 4th-order continuous extension (Hairer's contd5).
    static constexpr double d[7] = {-12715105075.0 / 11282082432.0,  0.0,
                                    87487479700.0 / 32700410799.0,   -10690763975.0 / 1880347072.0,
                                    701980252875.0 / 199316789632.0, -1453857185.0 / 822651844.0,
                                    69997945.0 / 29380423.0};
    const std::size_t n = sys_.n;
    for (std::size_t i = 0; i < n; ++i) {
      const double ydiff = ynew_[i] - y_[i];
      const double bspl = h * k_[0][i] - ydiff;
      rcont_[0][i] = y_[i];
      rcont_[1][i] = ydiff;
      rcont_[2][i] = bspl;
      rcont_[3][i] = ydiff - h * k_[6][i] - bspl;
      double s = 0.0;
      for (int j = 0; j < 7; ++j) s += d[j] * k_[j][i];
      rcont_[4][i] = h * s;
    }
    y_prev_.swap(y_);
    f_prev_.swap(f_);
    std::copy(ynew_.begin(), ynew_.end(), y_.begin());
    std::copy(k_[6].begin(), k_[6].end(), f_.begin());
    t_prev_ = t_;
    t_ = t_new;
  }

  void dense(double t, double* out) const override {
    const double h = t_ - t_prev_;
    const double th = h > 0.0 ? (t - t_prev_) / h : 0.0, th1 = 1.0 - th;
    const std::size_t n = sys_.n;
    for (std::size_t i = 0; i < n; ++i)
      out[i] = rcont_[0][i] +
               th * (rcont_[1][i] + th1 * (rcont_[2][i] + th * (rcont_[3][i] + th1 * rcont_[4][i])));
  }

 private:
  std::vector<double> rcont_[5];
  std::vector<double> err_;
};

// ----------------------------------------------------------- DOP853
class Dop853 final : public Embedded {
 public:
  Dop853(OdeSystem s, IntegratorOptions o)
      : Embedded(std::move(s), o, kDop853Extended, 1.0 / 8.0, 0.0, 0.333, 6.0) {
    const std::size_t n = sys_.n;
    for (auto& r : rcont_) r.resize(n);
    err5_.resize(n);
    err3_.resize(n);
  }
  std::string name() const override { return "dop853"; }
  int order() const override { return 8; }

  double attempt(double h) override {
    const std::size_t n = sys_.n;
    std::copy(f_.begin(), f_.end(), k_[0].begin());  // FSAL
    for (int s = 1; s < kDop853Stages; ++s) {
      combine(kDop853A[s], s, h);
      eval(t_ + kDop853C[s] * h, tmp_.data(), k_[s].data());
    }
    combine(kDop853A[kDop853Stages], kDop853Stages, h);  // 8th-order solution
    std::copy(tmp_.begin(), tmp_.end(), ynew_.begin());
    double e5 = 0.0, e3 = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      double s5 = 0.0, s3 = 0.0;
      for (int j = 0; j < kDop853Stages; ++j) {
        s5 += kDop853E5[j] * k_[j][i];
        s3 += kDop853E3[j] * k_[j][i];
      }
      const double sk = opt_.atol + opt_.rtol * std::max(std::abs(y_[i]), std::abs(ynew_[i]));
      e5 += (s5 / sk) * (s5 / sk);
      e3 += (s3 / sk) * (s3 / sk);
    }
    double deno = e5 + 0.01 * e3;
    if (deno <= 0.0) deno = 1.0;
    const double n_norm = static_cast<double>(opt_.norm_size > 0 ? opt_.norm_size : n);
    return std::abs(h) * e5 * std::sqrt(1.0 / (n_norm * deno));
  }

  void accept(double h, double t_new) override {
    // f(t + h, y_new): FSAL stage 12, the next step's first stage.
    eval(t_ + h, ynew_.data(), k_[kDop853Stages].data());
    // The 7th-order continuous extension costs three more RHS evaluations
    // per step; like Hairer's dop853.f it is built only for steps that hold
    // an output time, i.e. on the first dense() call (prepare_dense).
    dense_ready_ = false;
    h_dense_ = h;
    y_prev_.swap(y_);
    f_prev_.swap(f_);
    std::copy(ynew_.begin(), ynew_.end(), y_.begin());
    std::copy(k_[kDop853Stages].begin(), k_[kDop853Stages].end(), f_.begin());
    t_prev_ = t_;
    t_ = t_new;
  }

  void dense(double t, double* out) const override {
    const std::size_t n = sys_.n;
    if (t_ == t_prev_) {  // no step taken yet (reset / restored state)
      std::copy(y_.begin(), y_.end(), out);
      return;
    }
    // Building the extension evaluates f, which is not a const operation;
    // the result is a cache of this step's continuous extension.
    if (!dense_ready_) const_cast<Dop853*>(this)->prepare_dense();
    const double h = t_ - t_prev_;
    const double s = h > 0.0 ? (t - t_prev_) / h : 0.0, s1 = 1.0 - s;
    for (std::size_t i = 0; i < n; ++i)
      out[i] =
          rcont_[0][i] +
          s * (rcont_[1][i] +
               s1 *
                   (rcont_[2][i] +
                    s * (rcont_[3][i] +
                         s1 * (rcont_[4][i] + s * (rcont_[5][i] + s1 * (rcont_[6][i] + s * rcont_[7][i]))))));
  }

 private:
  // Continuous extension of the last step [t_prev_, t_] (dop853.f, CONTD8),
  // from y_prev_, y_ and this step's stages k_ (still intact: the next
  // attempt() has not run yet).
  void prepare_dense() {
    const std::size_t n = sys_.n;
    const double h = h_dense_;
    const auto& f1 = k_[kDop853Stages];
    for (std::size_t i = 0; i < n; ++i) {
      const double ydiff = y_[i] - y_prev_[i];
      const double bspl = h * k_[0][i] - ydiff;
      rcont_[0][i] = y_prev_[i];
      rcont_[1][i] = ydiff;
      rcont_[2][i] = bspl;
      rcont_[3][i] = ydiff - h * f1[i] - bspl;
    }
    for (int r = 0; r < 4; ++r) {
      for (std::size_t i = 0; i < n; ++i) {
        double s = 0.0;
        for (int j = 0; j < kDop853Stages + 1; ++j) s += kDop853D[r][j] * k_[j][i];
        rcont_[4 + r][i] = s;
      }
    }
    // three extra stages for the 7th-order continuous extension, from y_prev_
    for (int s = kDop853Stages + 1; s < kDop853Extended; ++s) {
      const double* a = kDop853A[s];
      std::copy(y_prev_.begin(), y_prev_.end(), tmp_.begin());
      for (int j = 0; j < s; ++j) {
        if (a[j] == 0.0) continue;
        const double c = h * a[j];
        const double* kj = k_[j].data();
        for (std::size_t i = 0; i < n; ++i) tmp_[i] += c * kj[i];
      }
      eval(t_prev_ + kDop853C[s] * h, tmp_.data(), k_[s].data());
      for (int r = 0; r < 4; ++r) {
        const double dr = kDop853D[r][s];
        for (std::size_t i = 0; i < n; ++i) rcont_[4 + r][i] += dr * k_[s][i];
      }
    }
    for (int r = 4; r < 8; ++r)
      for (std::size_t i = 0; i < n; ++i) rcont_[r][i] *= h;
    dense_ready_ = true;
  }

  bool dense_ready_ = false;
  double h_dense_ = 0.0;
  std::vector<double> rcont_[8];
  std::vector<double> err5_, err3_;
};

}  // namespace

TimeIntegrator::TimeIntegrator(OdeSystem system, IntegratorOptions options)
    : sys_(std::move(system)), opt_(options) {
  if (sys_.n == 0 || !sys_.f) throw InputError("time integrator: empty ODE system");
  if (!(opt_.dt > 0.0) || !std::isfinite(opt_.dt))
    throw InputError("solver.dt must be positive and finite, got " + message_number(opt_.dt));
  if (!(opt_.rtol >= 0.0) || !(opt_.atol >= 0.0) || (opt_.rtol == 0.0 && opt_.atol == 0.0))
    throw InputError("solver.rtol and solver.atol must be >= 0 and not both 0");
  y_.resize(sys_.n);
  f_.resize(sys_.n);
  y_prev_.resize(sys_.n);
  f_prev_.resize(sys_.n);
}

void TimeIntegrator::reset(double t0, const double* y0) {
  std::copy(y0, y0 + sys_.n, y_.begin());
  t_ = t_prev_ = t0;
  eval(t_, y_.data(), f_.data());
  y_prev_ = y_;
  f_prev_ = f_;
  restarted();
}

IntegratorState TimeIntegrator::save_state() const {
  IntegratorState s;
  s.t = t_;
  s.dt_next = h_;
  s.y = y_;
  s.f = f_;
  s.controller = controller_memory();
  s.steps = steps_;
  s.rejected = rejected_;
  s.rhs_evaluations = rhs_evals_;
  return s;
}

void TimeIntegrator::restore_state(const IntegratorState& s) {
  if (s.y.size() != sys_.n || s.f.size() != sys_.n)
    throw InputError(name() + ": saved state has " + std::to_string(s.y.size()) + " values, the system has " +
                     std::to_string(sys_.n));
  y_ = s.y;
  f_ = s.f;
  y_prev_ = y_;
  f_prev_ = f_;
  t_ = t_prev_ = s.t;
  h_ = s.dt_next;
  set_controller_memory(s.controller);
  steps_ = s.steps;
  rejected_ = s.rejected;
  rhs_evals_ = s.rhs_evaluations;
  restarted();
}

void TimeIntegrator::rk4_step(double t, const double* y0, const double* f0, double h, double* y1) {
  const std::size_t n = sys_.n;
  if (rk_tmp_.size() != n) {
    rk_k2_.resize(n);
    rk_k3_.resize(n);
    rk_k4_.resize(n);
    rk_tmp_.resize(n);
  }
  for (std::size_t i = 0; i < n; ++i) rk_tmp_[i] = y0[i] + 0.5 * h * f0[i];
  eval(t + 0.5 * h, rk_tmp_.data(), rk_k2_.data());
  for (std::size_t i = 0; i < n; ++i) rk_tmp_[i] = y0[i] + 0.5 * h * rk_k2_[i];
  eval(t + 0.5 * h, rk_tmp_.data(), rk_k3_.data());
  for (std::size_t i = 0; i < n; ++i) rk_tmp_[i] = y0[i] + h * rk_k3_[i];
  eval(t + h, rk_tmp_.data(), rk_k4_.data());
  for (std::size_t i = 0; i < n; ++i)
    y1[i] = y0[i] + h / 6.0 * (f0[i] + 2.0 * (rk_k2_[i] + rk_k3_[i]) + rk_k4_[i]);
}

bool TimeIntegrator::clamp(double& h, double t_stop) const {
  // Within a tiny relative distance of t_stop, finish exactly there rather
  // than leave a sliver step.
  const double remaining = t_stop - t_;
  if (h >= remaining * (1.0 - 1e-12) || remaining <= 1e-14 * std::max(1.0, std::abs(t_stop))) {
    h = remaining;
    return true;
  }
  return false;
}

void TimeIntegrator::check_steps() const {
  if (steps_ + rejected_ >= opt_.max_steps)
    throw NumericalError(name() + ": more than solver.max_steps = " + std::to_string(opt_.max_steps) +
                         " steps at t = " + message_number(t_) +
                         "; raise solver.max_steps or loosen the tolerances.");
}

void TimeIntegrator::hermite(double t, double* out) const {
  const double h = t_ - t_prev_;
  const double th = h > 0.0 ? (t - t_prev_) / h : 0.0;
  const std::size_t n = sys_.n;
  for (std::size_t i = 0; i < n; ++i) {
    const double y0 = y_prev_[i], y1 = y_[i];
    out[i] = (1.0 - th) * y0 + th * y1 +
             th * (th - 1.0) * ((1.0 - 2.0 * th) * (y1 - y0) + (th - 1.0) * h * f_prev_[i] + th * h * f_[i]);
  }
}

// -------------------------------------------------------- Brownian
// One step: the system's bath, the overdamped step over dt (brownian.hpp). Like the
// Langevin rod, the step index counts from the start of the run (restored with
// the checkpoint), so the noise of every step is that of an uninterrupted run,
// and frames fall on steps (the scene checks that dt divides the interval).
class Brownian final : public TimeIntegrator {
 public:
  Brownian(OdeSystem s, IntegratorOptions o) : TimeIntegrator(std::move(s), o) {
    if (!sys_.bath) throw InputError("solver.time = \"brownian\": the system has no overdamped step");
    h_ = opt_.dt;
  }
  std::string name() const override { return "brownian"; }
  bool adaptive() const override { return false; }
  int order() const override { return 1; }

  void step(double) override {
    check_steps();
    y_prev_ = y_;
    sys_.bath(steps_, y_.data());
    t_prev_ = t_;
    ++steps_;
    t_ = origin_ + static_cast<double>(steps_) * opt_.dt;
    project_end();
  }

  void dense(double t, double* out) const override {
    const double h = t_ - t_prev_;
    const double a = h > 0.0 ? (t - t_prev_) / h : 1.0;
    if (std::abs(a - 1.0) <= 1e-9 || h <= 0.0) {
      std::copy(y_.begin(), y_.end(), out);
      return;
    }
    for (std::size_t k = 0; k < y_.size(); ++k) out[k] = (1.0 - a) * y_prev_[k] + a * y_[k];
  }

 private:
  void restarted() override {
    origin_ = t_ - static_cast<double>(steps_) * opt_.dt;
    y_prev_ = y_;
  }
  std::vector<double> y_prev_;
  double origin_ = 0.0;
};

StepLimit step_limit(TimeMethod kind) {
  switch (kind) {
    case TimeMethod::rk4:
      return {kRK4ImaginaryBound, "RK4", ", fewer rod.points, or an adaptive solver.time"};
    case TimeMethod::langevin:  // its conservative part is one RK4 step
      return {kRK4ImaginaryBound, "RK4", " or fewer rod.points"};
    default:
      return {};
  }
}

std::unique_ptr<TimeIntegrator> make_time_integrator(TimeMethod kind, OdeSystem system,
                                                     const IntegratorOptions& options) {
  switch (kind) {
    case TimeMethod::rk4:
      return std::make_unique<RK4>(std::move(system), options);
    case TimeMethod::rk4_doubling:
      return std::make_unique<RK4Doubling>(std::move(system), options);
    case TimeMethod::dopri5:
      return std::make_unique<Dopri5>(std::move(system), options);
    case TimeMethod::dop853:
      return std::make_unique<Dop853>(std::move(system), options);
    case TimeMethod::langevin:
      return std::make_unique<Langevin>(std::move(system), options);
    case TimeMethod::brownian:
      return std::make_unique<Brownian>(std::move(system), options);
    case TimeMethod::automatic:
      break;
  }
  throw InputError("solver.time = \"" + to_string(kind) +
                   "\" is not a time integrator; allowed: \"rk4\", \"rk4-doubling\", \"dopri5\", \"dop853\", "
                   "\"langevin\", \"brownian\"");
}

}  // namespace rodcore
