#include "rodcore/simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "rodcore/diagnostics.hpp"
#include "rodcore/error.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/reconstruction.hpp"
#include "rodcore/reduced_planar.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/stability.hpp"

namespace rodcore {
namespace {

std::string num(double x) {
  std::ostringstream o;
  o.precision(6);
  o << x;
  return o.str();
}

const char* planar_name(Planar p) { return p == Planar::omega2 ? "omega2" : "omega1"; }

const char* kComponentNames[12] = {"gamma1", "gamma2", "gamma3", "omega1", "omega2", "omega3",
                                   "Gamma1", "Gamma2", "Gamma3", "Omega1", "Omega2", "Omega3"};

// Relative high-wavenumber content of the initial fields: |D f - D_2/3 f| /
// |D f| over all 12 rows, D the spectral derivative and D_2/3 the same with
// the top third of the modes removed. Round-off (~1e-15) for smooth
// (analytic) fields; O(N^-1/2) or more for a jump or grid-scale noise.
double spectral_tail(const Scene& sc, const std::vector<double>& y) {
  const std::size_t N = static_cast<std::size_t>(sc.rod.points);
  const auto full = make_derivative_operator("spectral", N, sc.rod.length, false);
  const auto cut = make_derivative_operator("spectral", N, sc.rod.length, true);
  std::vector<double> a(12 * N), b(12 * N);
  full->apply(y.data(), a.data(), 12);
  cut->apply(y.data(), b.data(), 12);
  double num2 = 0.0, den2 = 0.0;
  for (std::size_t i = 0; i < 12 * N; ++i) {
    num2 += (a[i] - b[i]) * (a[i] - b[i]);
    den2 += a[i] * a[i];
  }
  return den2 > 0.0 ? std::sqrt(num2 / den2) : 0.0;
}

// Threshold of spectral_tail above which the initial fields count as
// non-smooth and FD4 is chosen (docs/performance.md: with grid-scale content
// FD4 takes about half the steps of spectral at the same tolerance).
constexpr double kSmoothTail = 1e-6;

// solver.space / solver.time = "auto" -> the measured default
// (docs/performance.md, "Default method rule"); `note` says what and why.
void resolve_method(Scene& sc, std::string& note) {
  std::string why_space = "solver.space = \"" + sc.solver.space + "\" as given";
  if (sc.solver.space == "auto") {
    if (sc.solver.dealias || sc.rod.points < 5) {
      sc.solver.space = "spectral";
      why_space = sc.solver.dealias ? "spectral (auto: solver.dealias asks for it)"
                                    : "spectral (auto: fd4 needs at least 5 points)";
    } else {
      const double tail = spectral_tail(sc, make_initial_state(sc));
      sc.solver.space = tail > kSmoothTail ? "fd4" : "spectral";
      why_space = sc.solver.space + " (auto: high-wavenumber content of the initial fields " + num(tail) +
                  (tail > kSmoothTail ? " > " : " <= ") + num(kSmoothTail) +
                  (tail > kSmoothTail ? ", non-smooth)" : ", smooth)");
    }
  }
  std::string why_time = "solver.time = \"" + sc.solver.time + "\" as given";
  if (sc.solver.time == "auto") {
    sc.solver.time = "dop853";
    why_time = "dop853 (auto: the fastest at errors <= 1e-6 in the benchmarks)";
  }
  note = why_space + "; " + why_time;
}

}  // namespace

struct Simulation::Impl {
  Scene scene;
  std::size_t N = 0;
  std::unique_ptr<DerivativeOperator> op;
  std::unique_ptr<RodRHS> rhs;
  std::unique_ptr<Reconstructor> rec;
  bool reconstruct = false;
  std::vector<double> y0;     // 12 N (+ 7: anchor q(0,t), r(0,t))
  std::vector<double> state;  // current 12 N
  double t = 0.0;
  std::vector<double> s;
  CheckpointHooks hooks;
  std::optional<Checkpoint> resume;
  // Reduced planar system (solver.reduce = "auto", reduced_planar.hpp):
  // the polarisation the initial state lies in, exactly, and why (not).
  std::optional<Planar> planar;
  std::string reduce_note;
  Scene given;              // the scene as given ("auto" kept): what checkpoints record
  std::string method_note;  // how the method was chosen

  double wave_speed() const {
    const Material& m = scene.material;
    double c = 1.0;
    for (int i = 0; i < 3; ++i) {
      c = std::max(c, std::sqrt(std::max(0.0, m.C[i])));
      c = std::max(c, std::sqrt(std::max(0.0, m.D[i]) / m.I[i]));
    }
    return c;
  }
};

Simulation::Simulation(const Scene& scene) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.scene = scene;
  Scene& sc = d.scene;
  const InitialKind& kind = initial_kind(sc.initial.kind);
  // A scene built in code may leave the rod to the kind (e.g. dna_planar).
  if (kind.derive_rod && (sc.rod.length <= 0.0 || sc.rod.points <= 0)) {
    std::set<std::string> keys;
    if (sc.rod.points > 0) keys.insert("points");
    kind.derive_rod(sc.initial, sc.rod, sc.material, keys);
  }
  if (sc.rod.points <= 0 || !(sc.rod.length > 0.0) || !std::isfinite(sc.rod.length))
    throw InputError(sc.source + ": rod.points and rod.length must be positive (got points = " +
                     std::to_string(sc.rod.points) + ", length = " + num(sc.rod.length) + ")");
  if (sc.output.frames < 1) throw InputError(sc.source + ": output.frames must be >= 1");
  if (!(sc.output.t_end >= 0.0) || !std::isfinite(sc.output.t_end))
    throw InputError(sc.source + ": output.t_end must be >= 0 and finite");
  if (sc.solver.reduce != "auto" && sc.solver.reduce != "off")
    throw InputError(sc.source + ": solver.reduce = \"" + sc.solver.reduce +
                     "\" is not known; allowed: \"auto\", \"off\"");
  d.N = static_cast<std::size_t>(sc.rod.points);
  d.given = sc;
  resolve_method(sc, d.method_note);
  d.op = make_derivative_operator(sc.solver.space, d.N, sc.rod.length, sc.solver.dealias);
  d.rhs = std::make_unique<RodRHS>(sc.rod, sc.material, *d.op);
  d.reconstruct = sc.output.centerline || sc.output.directors;
  if (d.reconstruct) d.rec = std::make_unique<Reconstructor>(d.N, sc.rod.length);
  d.s.resize(d.N);
  for (std::size_t i = 0; i < d.N; ++i)
    d.s[i] = static_cast<double>(i) * sc.rod.length / static_cast<double>(d.N);

  d.state = make_initial_state(sc);
  if (long bad = first_non_finite(d.state.data(), d.state.size()); bad >= 0) {
    const std::size_t r = static_cast<std::size_t>(bad) / d.N, i = static_cast<std::size_t>(bad) % d.N;
    throw InputError(sc.source + ": initial field " + kComponentNames[r] + " is not finite (" +
                     num(d.state[bad]) + ") at point " + std::to_string(i) + " (s = " + num(d.s[i]) +
                     ")");
  }
  d.y0 = d.state;
  if (d.reconstruct) {
    const auto [q0, r0] = initial_anchor(sc);
    d.y0.insert(d.y0.end(), q0.begin(), q0.end());
    d.y0.insert(d.y0.end(), r0.begin(), r0.end());
  }
  if (sc.solver.reduce == "off") {
    d.reduce_note = "full system (solver.reduce = \"off\")";
  } else if (!planar_reduction_allowed(sc.rod)) {
    d.reduce_note = "full system: the intrinsic shape is not uniform Gamma0 = (0, 0, G03), Omega0 = 0";
  } else if ((d.planar = planar_polarisation(d.state.data(), d.N))) {
    d.reduce_note = std::string("reduced planar system (") + planar_name(*d.planar) +
                    " polarisation, 6 of 12 rows; paper Sec 4.1)";
  } else {
    d.reduce_note = "full system: the initial state is not exactly planar";
  }
  // Make sure the integrator kind is known now (InputError), not in run().
  bool known = false;
  for (const auto& k : time_integrator_kinds()) known = known || k == sc.solver.time;
  if (!known)
    throw InputError(sc.source + ": solver.time = \"" + sc.solver.time +
                     "\" is not known; allowed: \"rk4\", \"rk4-doubling\", \"dopri5\", \"dop853\"");
}

Simulation::~Simulation() = default;

void Simulation::set_checkpoint_hooks(CheckpointHooks hooks) { impl_->hooks = std::move(hooks); }

void Simulation::resume_from(const Checkpoint& c) {
  const Impl& d = *impl_;
  // The scene text itself is compared by check_checkpoint_matches (rodsim);
  // here only what would make the run meaningless or unsafe.
  if (c.method != d.scene.solver.time)
    throw InputError(d.scene.source + ": the checkpoint was made with solver.time = \"" + c.method +
                     "\", the scene asks for \"" + d.scene.solver.time + "\"");
  if (!c.reduced.empty() && !planar_reduction_allowed(d.scene.rod))
    throw InputError(d.scene.source + ": the checkpoint holds the reduced planar system (" + c.reduced +
                     "), which this scene's intrinsic shape does not allow");
  const std::size_t need = d.y0.size() - (c.reduced.empty() ? 0 : 6 * d.N);
  if (c.integrator.y.size() != need)
    throw InputError(d.scene.source + ": the checkpoint holds " + std::to_string(c.integrator.y.size()) +
                     " state values, this scene needs " + std::to_string(need) +
                     (c.reduced.empty() ? "" : " (reduced planar system)"));
  if (c.next_frame < 1 || c.next_frame > d.scene.output.frames)
    throw InputError(d.scene.source + ": the checkpoint's next frame " + std::to_string(c.next_frame) +
                     " is outside 1.." + std::to_string(d.scene.output.frames));
  impl_->resume = c;
}

const Scene& Simulation::scene() const { return impl_->scene; }
std::vector<double> Simulation::grid() const { return impl_->s; }
const std::vector<double>& Simulation::state() const { return impl_->state; }
double Simulation::time() const { return impl_->t; }

RunSummary Simulation::run(const FrameHandler& on_frame, const ProgressHandler& progress) {
  Impl& d = *impl_;
  const Scene& sc = d.scene;
  const std::size_t N = d.N;
  const auto wall0 = std::chrono::steady_clock::now();
  RunSummary summary;
  summary.method = d.op->name() + "+" + sc.solver.time;

  // Explicit fixed step: RK4 is stable on the imaginary axis up to
  // |lambda dt| = 2 sqrt 2 ~ 2.83; we allow 2.8 (1 % margin). For a uniform
  // intrinsic shape lambda is exact: the spectral radius of the system
  // linearised about the rest state over every wavenumber the operator
  // resolves (stability.hpp). For an s-varying shape only the wave-speed
  // estimate c_max k_max is available (it leaves out the lower-order terms,
  // which raised the true radius by up to 1.6x on the DNA rod).
  if (sc.solver.time == "rk4") {
    const bool uniform = sc.rod.Gamma0_s.empty() && sc.rod.Omega0_s.empty();
    const double lambda = uniform ? linear_spectral_radius(*d.rhs) : d.wave_speed() * d.op->max_wavenumber();
    const double dt_cfl = 2.8 / lambda;
    if (sc.solver.dt > dt_cfl)
      throw NumericalError(
          sc.source + ": solver.dt = " + num(sc.solver.dt) + " exceeds the RK4 stability limit " + num(dt_cfl) +
          (uniform ? " (2.8 / spectral radius " + num(lambda) + " of the equations linearised about the rest state, "
                   : " (estimate: 2.8 / (max wave speed " + num(d.wave_speed()) + " x max wavenumber " +
                         num(d.op->max_wavenumber()) + "), ") +
          d.op->name() + "); use solver.dt <= " + num(dt_cfl * (1.0 - 5e-6)) + ", fewer rod.points, or an adaptive solver.time");
  }

  // The integrated system: the full 12 rows, or only the 6 rows of a planar
  // polarisation (PlanarRHS evaluates the same RodRHS). `rows` maps the
  // integrated rows to state rows; the 7 anchor values follow in both cases.
  std::optional<Planar> planar = d.planar;
  if (d.resume) planar = d.resume->reduced.empty() ? std::nullopt
                         : std::optional<Planar>(d.resume->reduced == "omega2" ? Planar::omega2 : Planar::omega1);
  summary.reduce_note = d.reduce_note;
  summary.method_note = d.method_note;
  if (d.resume && planar != d.planar)
    summary.reduce_note = planar ? "reduced planar system (as in the checkpoint)"
                                 : "full system (as in the checkpoint: the run had left the reduced system)";
  const bool recon = d.reconstruct;
  RodRHS* rhs = d.rhs.get();
  std::unique_ptr<PlanarRHS> planar_rhs;
  std::vector<int> rows;
  OdeSystem sys;
  auto make_system = [&]() {
    planar_rhs.reset();
    rows.clear();
    if (planar) {
      planar_rhs = std::make_unique<PlanarRHS>(*rhs, *planar);
      rows.assign(planar_rhs->rows().begin(), planar_rhs->rows().end());
    } else {
      for (int r = 0; r < 12; ++r) rows.push_back(r);
    }
    const std::size_t nrows = rows.size();
    sys.n = nrows * N + (recon ? 7 : 0);
    // Rows of omega and gamma in the integrated state (-1: identically zero).
    std::array<int, 6> at{-1, -1, -1, -1, -1, -1};
    for (std::size_t k = 0; k < nrows; ++k)
      if (rows[k] < 6) at[rows[k]] = static_cast<int>(k);
    PlanarRHS* pr = planar_rhs.get();
    sys.f = [rhs, pr, N, nrows, recon, at](double, const double* y, double* f) {
      if (pr) (*pr)(y, f);
      else (*rhs)(y, f);
      if (recon) {
        auto v = [&](int r) { return at[r] < 0 ? 0.0 : y[at[r] * N]; };
        const Vec3 w0{v(3), v(4), v(5)};
        const Vec3 g0{v(0), v(1), v(2)};
        anchor_rate(y + nrows * N, w0, g0, f + nrows * N);
      }
    };
  };
  make_system();
  // Integrated state -> full state (12 N + anchor) in `full`.
  std::vector<double> full(d.y0.size(), 0.0);
  auto expand = [&](const double* y) -> const double* {
    if (!planar_rhs) return y;
    planar_rhs->expand(y, full.data());
    std::copy(y + 6 * N, y + 6 * N + (recon ? 7 : 0), full.data() + 12 * N);
    return full.data();
  };
  IntegratorOptions io;
  io.rtol = sc.solver.rtol;
  io.atol = sc.solver.atol;
  io.dt = sc.solver.dt;
  io.dt_min = sc.solver.dt_min;
  io.max_steps = sc.solver.max_steps;
  io.norm_size = d.y0.size();  // the skipped rows count as the zeros they are
  auto integ = make_time_integrator(sc.solver.time, sys, io);
  double wall_before = 0.0;
  if (d.resume) {
    integ->restore_state(d.resume->integrator);
    wall_before = d.resume->wall_seconds;
    summary.energy_drift = d.resume->energy_drift;
  } else if (planar_rhs) {
    std::vector<double> y0r(sys.n);
    planar_rhs->reduce(d.y0.data(), y0r.data());
    std::copy(d.y0.begin() + 12 * N, d.y0.end(), y0r.begin() + 6 * N);
    integ->reset(0.0, y0r.data());
  } else {
    integ->reset(0.0, d.y0.data());
  }
  // Guard of the reduction, at steps that deliver a frame: the full RHS at
  // the (expanded) state must leave the six skipped rows exactly zero. It
  // always does in exact and in floating-point arithmetic (every term feeding
  // them is a product with a zero), so this only catches the impossible; if
  // it ever fails the run continues on the full system from that step.
  std::vector<double> f_guard;
  auto planar_guard_holds = [&](const double* y12) {
    f_guard.resize(12 * N);
    (*rhs)(y12, f_guard.data());
    for (int r : planar_zero_rows(*planar))
      for (std::size_t i = 0; i < N; ++i)
        if (f_guard[r * N + i] != 0.0) return false;
    return true;
  };

  const auto Gamma0 = d.rhs->Gamma0();
  const auto Omega0 = d.rhs->Omega0();
  const double h = sc.rod.length / static_cast<double>(N);
  double E0 = std::numeric_limits<double>::quiet_NaN();
  std::vector<double> buf(d.y0.size()), centerline, directors;
  if (sc.output.centerline) centerline.resize(3 * N);
  if (sc.output.directors) directors.resize(9 * N);

  const bool energy_every_frame =
      sc.output.energy || sc.output.energy_parts || std::isfinite(sc.checks.max_energy_drift);
  auto deliver = [&](int index, double t, const double* y) {
    Frame fr;
    fr.index = index;
    fr.t = t;
    fr.N = N;
    fr.y = y;
    // Energy only where it is asked for: every frame when it is output or a
    // drift bound is set; otherwise at the first and the last frame only, so
    // that the summary's drift (then end-to-end) and the overflow check of
    // the initial fields stay (O(N) each; docs/numerics.md).
    if (energy_every_frame || index == 0 || index == sc.output.frames - 1) {
      const EnergyParts parts = energy_parts(y, N, h, sc.material, Gamma0, Omega0);
      const double E = parts.total();
      if (!std::isfinite(E))
        throw NumericalError(sc.source + ": the energy is not finite (E = " + num(E) + ") at t = " + num(t) +
                             (index == 0 ? ": the initial fields are so large that their squares overflow; check "
                                           "the initial fields and their units (dimensionless, paper Sec 2.2)"
                                         : ": the run blew up; reduce solver.dt or tolerances, or raise rod.points"));
      if (index == 0) E0 = E;
      const double drift = std::abs(E0) > 0.0 ? std::abs(E - E0) / std::abs(E0) : std::abs(E - E0);
      summary.energy_drift = std::max(summary.energy_drift, drift);
      if (!(drift <= sc.checks.max_energy_drift))
        throw NumericalError(sc.source + ": relative energy drift " + num(drift) + " at t = " +
                             num(t) + " exceeds checks.max_energy_drift = " +
                             num(sc.checks.max_energy_drift) +
                             "; tighten solver.rtol/atol, reduce dt, or raise rod.points");
      if (sc.output.energy || sc.output.energy_parts) fr.energy = E;
      if (sc.output.energy_parts) fr.energy_parts = parts.as_map();
    }
    if (recon) {
      const Quat q0{y[12 * N], y[12 * N + 1], y[12 * N + 2], y[12 * N + 3]};
      const Vec3 r0{y[12 * N + 4], y[12 * N + 5], y[12 * N + 6]};
      const auto end = d.rec->sweep(y, q0, r0, centerline.empty() ? nullptr : centerline.data(),
                                    directors.empty() ? nullptr : directors.data());
      const Quat qn = quat_normalized(q0);
      const Quat rel = quat_mul(Quat{qn[0], -qn[1], -qn[2], -qn[3]}, end.q);  // R(0)^T R(L)
      const double vn = std::sqrt(rel[1] * rel[1] + rel[2] * rel[2] + rel[3] * rel[3]);
      fr.end_rotation = 2.0 * std::atan2(vn, std::abs(rel[0]));
      fr.end_to_end = Vec3{end.r[0] - r0[0], end.r[1] - r0[1], end.r[2] - r0[2]};
      fr.max_director_norm_error = d.rec->max_director_norm_error();
      if (fr.max_director_norm_error > sc.checks.max_director_norm_error)
        throw NumericalError(sc.source + ": director norm error " +
                             num(fr.max_director_norm_error) + " at t = " + num(t) +
                             " exceeds checks.max_director_norm_error = " +
                             num(sc.checks.max_director_norm_error) +
                             ". Directors are unit quaternions, exact to round-off (~1e-15): a larger error "
                             "means non-finite or huge curvatures Omega; check the fields, or raise the bound "
                             "if it is below round-off");
      if (!centerline.empty()) fr.centerline = centerline.data();
      if (!directors.empty()) fr.directors = directors.data();
    }
    if (on_frame) on_frame(fr);
  };

  const int frames = sc.output.frames;
  const double t_end = sc.output.t_end;
  auto frame_time = [&](int j) {
    return (j == frames - 1 || frames == 1) ? (j == 0 && frames == 1 ? 0.0 : t_end)
                                            : t_end * static_cast<double>(j) /
                                                  static_cast<double>(frames - 1);
  };
  int j = 1;
  if (d.resume) {
    E0 = d.resume->E0;
    j = d.resume->next_frame;
    d.resume.reset();
  } else {
    deliver(0, 0.0, expand(integ->y().data()));
    while (j < frames && t_end == 0.0) deliver(j++, 0.0, expand(integ->y().data()));
  }

  while (j < frames) {
    integ->step(t_end);
    const double t = integ->t();
    const double* y = integ->y().data();
    if (long bad = first_non_finite(y, sys.n); bad >= 0) {
      std::string where = "the s = 0 frame";
      if (static_cast<std::size_t>(bad) < rows.size() * N) {
        const std::size_t k = static_cast<std::size_t>(bad) / N, i = static_cast<std::size_t>(bad) % N;
        where = std::string(kComponentNames[rows[k]]) + " at s = " + num(d.s[i]);
      }
      throw NumericalError(sc.source + ": non-finite value (NaN/Inf) in " + where + ", t = " +
                           num(t) + ". The run blew up: reduce solver.dt or tolerances, raise "
                           "rod.points, or check the initial fields.");
    }
    if (sc.checks.stop_on_fold) {
      // Gamma3 is integrated in both systems (row k3 of the integrated state).
      const std::size_t k3 = static_cast<std::size_t>(std::find(rows.begin(), rows.end(), 8) - rows.begin());
      const double* G3row = y + k3 * N;
      const std::size_t i = static_cast<std::size_t>(std::min_element(G3row, G3row + N) - G3row);
      const double G3 = G3row[i];
      if (G3 <= 0.0)
        throw NumericalError(sc.source + ": the rod folded (Gamma3 = " + num(G3) + " <= 0) at s = " +
                             num(d.s[i]) + ", t = " + num(t) +
                             ". The deformation is too large for the model: lower the amplitude, "
                             "or set checks.stop_on_fold = false to continue anyway.");
    }
    const bool frame_due = j < frames && frame_time(j) <= t;
    bool fall_back = false;
    if (frame_due && planar_rhs) fall_back = !planar_guard_holds(expand(y));
    while (j < frames && frame_time(j) <= t) {
      const double tj = frame_time(j);
      if (tj == t) {
        deliver(j, tj, expand(y));
      } else {
        integ->dense(tj, buf.data());
        deliver(j, tj, expand(buf.data()));
      }
      ++j;
    }
    if (fall_back) {
      const std::vector<double> y_full(expand(y), expand(y) + d.y0.size());
      const long steps = integ->steps(), rejected = integ->rejected(), evals = integ->rhs_evaluations();
      planar.reset();
      make_system();
      integ = make_time_integrator(sc.solver.time, sys, io);
      integ->reset(t, y_full.data());
      summary.steps += steps;
      summary.rejected += rejected;
      summary.rhs_evaluations += evals;
      summary.reduce_note = "reduced planar system until t = " + num(t) +
                            ", then the full system: the RHS of an out-of-plane row was not zero";
    }
    if (progress) progress(t, t_end);
    if (j < frames && d.hooks.due && d.hooks.save && d.hooks.due()) {
      Checkpoint c;
      c.scene = checkpoint_scene_text(d.given);
      c.method = sc.solver.time;
      c.integrator = integ->save_state();
      c.next_frame = j;
      c.E0 = E0;
      c.energy_drift = summary.energy_drift;
      c.reduced = planar ? planar_name(*planar) : "";
      c.wall_seconds = wall_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
      d.hooks.save(c);
    }
  }

  d.t = integ->t();
  const double* y_end = expand(integ->y().data());
  std::copy(y_end, y_end + 12 * N, d.state.begin());
  summary.steps += integ->steps();
  summary.rejected += integ->rejected();
  summary.rhs_evaluations += integ->rhs_evaluations();
  summary.reduced = planar.has_value();
  summary.wall_seconds =
      wall_before + std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
  return summary;
}

}  // namespace rodcore
