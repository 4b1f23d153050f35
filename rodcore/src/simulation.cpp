#include "rodcore/simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "rodcore/closure.hpp"
#include "rodcore/diagnostics.hpp"
#include "rodcore/error.hpp"
#include "rodcore/forces.hpp"
#include "rodcore/guards.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/message_number.hpp"
#include "rodcore/passage_guard.hpp"
#include "rodcore/reconstruction.hpp"
#include "rodcore/solver_choice.hpp"
#include "rodcore/stability.hpp"
#include "rodcore/system.hpp"
#include "rodcore/thermal.hpp"
#include "rodcore/topology.hpp"

namespace rodcore {
namespace {

std::string num(double x) { return message_number(x); }

}  // namespace

// The run loop over a System (system.hpp) and one TimeIntegrator: it makes the
// initial state and the frames, integrates the physics only through the System,
// and knows the scheme only through the integrators' protocol (integrators.hpp),
// its step limit included.
struct Simulation::Impl {
  Scene scene;
  Scene given;  // the scene as given ("auto" kept): what checkpoints record
  std::size_t N = 0;
  std::unique_ptr<RodSystem> system;
  std::unique_ptr<Reconstructor> rec;
  bool reconstruct = false;   // centerline or directors are output
  std::vector<double> y0;     // 12 N (+ 7: anchor q(0,t), r(0,t))
  std::vector<double> state;  // 12 N at time t
  double t = 0.0;
  std::vector<double> s;
  std::optional<Checkpoint> resume;
  // Reduced planar system (solver.reduce = "auto", reduced_planar.hpp): the
  // polarisation the initial state lies in, exactly, and why (not).
  std::optional<Planar> planar;
  std::string reduce_note;
  std::string method_note;                           // how the method was chosen
  std::vector<std::shared_ptr<Observer>> observers;  // the scene's checks first
  std::string thermal_note;                          // what the thermal sample did
  // A ring (topology.hpp is_closed on the initial centreline): its frames carry Lk, Tw, Wr.
  bool closed = false;
  const StrandPassageGuard* passage = nullptr;  // a ring with [contact] (owned by the System)

  // ---- the run, set up by start() on the first step_to()/run()
  bool started = false;
  IntegratorOptions io;
  std::unique_ptr<TimeIntegrator> integ;
  std::vector<double> buf, centerline, directors;
  std::vector<double> topo_x, topo_d;  // a ring's centreline and directors when the output has none
  double E0 = std::numeric_limits<double>::quiet_NaN();
  RunSummary summary;  // counters of integrators replaced by a fall-back, drift, notes
  double wall_before = 0.0, wall_spent = 0.0;  // wall seconds before a resume / in step_to() calls
  std::optional<std::chrono::steady_clock::time_point> call_start;  // during a step_to() call
  double wall_seconds() const {
    double w = wall_before + wall_spent;
    if (call_start)
      w += std::chrono::duration<double>(std::chrono::steady_clock::now() - *call_start).count();
    return w;
  }
  int j = 0;  // next output frame
  bool energy_every_frame = false;

  double frame_time(int k) const {
    const int frames = scene.output.frames;
    const double t_end = scene.output.t_end;
    return (k == frames - 1 || frames == 1)
               ? (k == 0 && frames == 1 ? 0.0 : t_end)
               : t_end * static_cast<double>(k) / static_cast<double>(frames - 1);
  }

  void make_thermal_state(const RigidMotion& g0);
  void add_contact();
  void start(const Simulation& self);
  void start_integrator(std::optional<Planar> planar_run, double t0, const double* y_full);
  void deliver(const Simulation& self, int index, double t, const double* y);
  void advance(const Simulation& self, double t_req);
  void leave_reduction(double ti);
};

// The [thermal] state: thermal.keep_closure holds the box of the [initial] state, taken
// before the sample is added: where the sampler's closure stays at linear order its sample is
// off the box by that gap (0.91 L seen on the 158-bp rod at 300 K), and a run holding the
// sample's own box would lose its slack tension (docs/thermal.md, "Closure in a run"). The
// sample itself is left as drawn (its statistics are the sampler's;
// tests/python/test_thermal_sampler.py).
void Simulation::Impl::make_thermal_state(const RigidMotion& g0) {
  const Scene& sc = scene;
  if (!sc.thermal.on) return;
  std::unique_ptr<ClosureHold> hold;
  if (sc.thermal.keep_closure) {
    hold = std::make_unique<ClosureHold>(sc, system->material());
    hold->hold_box_of(state.data(), g0);
  }
  thermal_note =
      sc.thermal.sample_initial
          ? add_thermal_sample(state, sc.rod.length, system->material(), sc.thermal.kT, sc.thermal.seed).note
          : "no thermal sample (thermal.sample_initial = false)";
  // No inertia: the velocities are not variables of the overdamped rod (its
  // output's gamma and omega are zero, its energy the potential energy).
  if (sc.solver.time == TimeMethod::brownian)
    std::fill(state.begin(), state.begin() + 6 * static_cast<long>(N), 0.0);
  thermal_note += bath_note(sc);
  if (!hold) return;
  // A sample that left the box (its closure at linear order only) is brought back by the
  // run's projections: each re-linearises at the current state (a few intervals).
  const double gap = hold->gap(state.data(), g0);
  if (gap > 1e-3)
    thermal_note +=
        "; the sample is off the initial state's box by " + num(gap) + ": the projections bring it back";
  thermal_note +=
      "; closure (the box motion of the initial state) restored " +
      (sc.thermal.closure_interval > 0.0 ? "every " + num(sc.thermal.closure_interval) + " time units"
                                         : std::string("every step")) +
      " by the least strain change in the energy metric";
  system->add_after_step(std::move(hold));
}

// A ring or a box-periodic rod, from the initial centreline (the frame at s = 0 does not
// matter): rings get Lk, Tw, Wr in every frame; with [contact], the self-contact force.
void Simulation::Impl::add_contact() {
  std::vector<double> x(3 * N);
  const auto end = rec->sweep(state.data(), Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, x.data(), nullptr);
  closed = topology::is_closed(x.data(), N);
  if (!scene.contact.on) return;
  const double period = std::sqrt(end.r[0] * end.r[0] + end.r[1] * end.r[1] + end.r[2] * end.r[2]);
  system->add_force(make_contact_force(scene, *system, closed, period));
  if (closed) {  // its Lk may not change: checked after every step, after the closure hold
    auto guard = std::make_unique<StrandPassageGuard>(N, scene.rod.length, state.data());
    passage = guard.get();
    system->add_after_step(std::move(guard));
  }
}

Simulation::Simulation(const Scene& scene, InitialState initial) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.scene = scene;
  Scene& sc = d.scene;
  validate_run_settings(sc);
  d.N = static_cast<std::size_t>(sc.rod.points);
  if (initial.y.size() != kComponents * d.N)
    throw InputError(sc.source + ": the initial state has " + std::to_string(initial.y.size()) +
                     " values; rod.points = " + std::to_string(d.N) + " needs 12 x " + std::to_string(d.N));
  d.given = sc;
  resolve_method(sc, initial.y, d.method_note);
  d.reconstruct = sc.output.centerline || sc.output.directors;
  // The frame at s = 0 is integrated when the output reconstructs or the closure is held.
  const bool anchor = d.reconstruct || (sc.thermal.on && sc.thermal.keep_closure);
  d.system = std::make_unique<RodSystem>(sc, anchor);
  d.rec = std::make_unique<Reconstructor>(d.N, sc.rod.length);
  d.s.resize(d.N);
  for (std::size_t i = 0; i < d.N; ++i)
    d.s[i] = static_cast<double>(i) * sc.rod.length / static_cast<double>(d.N);

  d.state = std::move(initial.y);
  check_initial_finite(sc, d.state, d.s);
  d.make_thermal_state(RigidMotion{initial.q0, initial.r0});
  d.add_contact();
  d.y0 = d.state;
  if (anchor) {
    d.y0.insert(d.y0.end(), initial.q0.begin(), initial.q0.end());
    d.y0.insert(d.y0.end(), initial.r0.begin(), initial.r0.end());
  }
  d.planar = choose_reduction(sc, d.system->material(), d.state.data(), d.N, d.reduce_note);
  // The scene's [checks], as the first observers (guards.hpp).
  for (auto& g : make_guards(sc, d.s)) d.observers.push_back(std::move(g));
}

Simulation::~Simulation() = default;

void Simulation::add_observer(std::shared_ptr<Observer> observer) {
  if (observer) impl_->observers.push_back(std::move(observer));
}

void Simulation::resume_from(const Checkpoint& c) {
  const Impl& d = *impl_;
  // The scene text itself is compared by check_checkpoint_matches (rodsim);
  // here only what would make the run meaningless or unsafe.
  if (d.started)
    throw InputError(d.scene.source + ": resume_from() must come before the first step_to()/run()");
  if (c.method != d.scene.solver.time)
    throw InputError(d.scene.source + ": the checkpoint was made with solver.time = \"" +
                     to_string(c.method) + "\", the scene asks for \"" + to_string(d.scene.solver.time) +
                     "\"");
  const std::optional<Planar> planar = planar_from_name(c.reduced);
  if (!c.reduced.empty() && (!planar || !reduction_allowed(d.scene, d.system->material(), *planar)))
    throw InputError(d.scene.source + ": the checkpoint holds the reduced planar system (" + c.reduced +
                     "), which this scene's intrinsic shape or material does not allow");
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
const Scene& Simulation::given_scene() const { return impl_->given; }
std::vector<double> Simulation::grid() const { return impl_->s; }
const std::vector<double>& Simulation::state() const { return impl_->state; }
double Simulation::time() const { return impl_->t; }
double Simulation::integrator_time() const { return impl_->integ ? impl_->integ->t() : impl_->t; }
int Simulation::frames_delivered() const { return impl_->started ? impl_->j : 0; }
double Simulation::frame_time(int index) const { return impl_->frame_time(index); }

double Simulation::kinetic_kT() const {
  const Impl& d = *impl_;
  return rodcore::kinetic_kT(d.state.data(), d.N, d.scene.rod.length / static_cast<double>(d.N),
                             d.system->material());
}

double Simulation::energy() const { return impl_->system->energy_parts(impl_->state.data()).total(); }

std::map<std::string, double> Simulation::energy_parts() const {
  return impl_->system->energy_parts(impl_->state.data()).as_map();
}

void Simulation::rhs(const double* y, double* dydt) const { impl_->system->rhs(y, dydt); }

// The integrator of solver.time on the System's ODE (full, or the planar
// polarisation `planar_run`), from the full state y_full at t0 (or none: a
// resumed run restores its own).
void Simulation::Impl::start_integrator(std::optional<Planar> planar_run, double t0, const double* y_full) {
  system->integrate(planar_run);
  integ = make_time_integrator(scene.solver.time, system->ode(), io);
  if (!y_full) return;
  if (!planar_run) {
    integ->reset(t0, y_full);
    return;
  }
  std::vector<double> y(integ->size());
  system->reduce(y_full, y.data());
  integ->reset(t0, y.data());
}

void Simulation::Impl::start(const Simulation& self) {
  const Scene& sc = scene;
  started = true;
  summary.method = system->elastic().op().name() + "+" + to_string(sc.solver.time);
  check_step_limit(sc, system->elastic(), step_limit(sc.solver.time));  // whichever scheme (stability.hpp)
  system->set_bath(make_bath(sc, *system));  // friction and noise of solver.time, if any (forces.hpp)

  std::optional<Planar> planar_run = planar;
  if (resume) planar_run = planar_from_name(resume->reduced);
  summary.reduce_note = reduce_note;
  summary.method_note = method_note;
  summary.thermal_note = thermal_note;
  if (resume && planar_run != planar)
    summary.reduce_note = planar_run
                              ? "reduced planar system (as in the checkpoint)"
                              : "full system (as in the checkpoint: the run had left the reduced system)";
  io.rtol = sc.solver.rtol;
  io.atol = sc.solver.atol;
  io.dt = sc.solver.dt;
  io.dt_min = sc.solver.dt_min;
  io.max_steps = sc.solver.max_steps;
  io.norm_size = y0.size();  // the skipped rows count as the zeros they are
  start_integrator(planar_run, 0.0, resume ? nullptr : y0.data());
  if (resume) {
    integ->restore_state(resume->integrator);
    wall_before = resume->wall_seconds;
    summary.energy_drift = resume->energy_drift;
  }
  buf.resize(y0.size());
  if (sc.output.centerline) centerline.resize(3 * N);
  if (sc.output.directors) directors.resize(9 * N);
  energy_every_frame =
      sc.output.energy || sc.output.energy_parts || std::isfinite(sc.checks.max_energy_drift);

  for (auto& o : observers) o->started(self);
  j = 1;
  if (resume) {
    E0 = resume->E0;
    j = resume->next_frame;
    resume.reset();
  } else {
    deliver(self, 0, 0.0, system->expand(integ->y().data()));
    while (j < sc.output.frames && sc.output.t_end == 0.0)
      deliver(self, j++, 0.0, system->expand(integ->y().data()));
  }
}

void Simulation::Impl::deliver(const Simulation& self, int index, double tf, const double* y) {
  const Scene& sc = scene;
  Frame fr;
  fr.index = index;
  fr.t = tf;
  fr.N = N;
  fr.y = y;
  // Energy only where it is asked for: every frame when it is output or a
  // drift bound is set; otherwise at the first and the last frame only, so
  // that the summary's drift (then end-to-end) and the overflow check of
  // the initial fields stay (O(N) each; docs/numerics.md).
  if (energy_every_frame || index == 0 || index == sc.output.frames - 1) {
    const EnergyParts e = system->energy_parts(y);
    const double E = e.total();
    if (index == 0) E0 = E;
    const double drift = std::abs(E0) > 0.0 ? std::abs(E - E0) / std::abs(E0) : std::abs(E - E0);
    summary.energy_drift = std::max(summary.energy_drift, drift);
    fr.checked_energy = E;
    fr.energy_drift = drift;
    if (sc.output.energy || sc.output.energy_parts) fr.energy = E;
    if (sc.output.energy_parts) fr.energy_parts = e.as_map();
  }
  if (reconstruct) {
    const Quat q0{y[12 * N], y[12 * N + 1], y[12 * N + 2], y[12 * N + 3]};
    const Vec3 r0{y[12 * N + 4], y[12 * N + 5], y[12 * N + 6]};
    const auto end = rec->sweep(y, q0, r0, centerline.empty() ? nullptr : centerline.data(),
                                directors.empty() ? nullptr : directors.data());
    const Quat qn = quat_normalized(q0);
    const Quat rel = quat_mul(Quat{qn[0], -qn[1], -qn[2], -qn[3]}, end.q);  // R(0)^T R(L)
    const double vn = std::sqrt(rel[1] * rel[1] + rel[2] * rel[2] + rel[3] * rel[3]);
    fr.end_rotation = 2.0 * std::atan2(vn, std::abs(rel[0]));
    fr.end_to_end = Vec3{end.r[0] - r0[0], end.r[1] - r0[1], end.r[2] - r0[2]};
    fr.max_director_norm_error = rec->max_director_norm_error();
    if (!centerline.empty()) fr.centerline = centerline.data();
    if (!directors.empty()) fr.directors = directors.data();
  }
  if (closed) {  // a ring: Lk, Tw, Wr of its centreline and the ribbon along d1
    const double* x = fr.centerline;
    const double* D = fr.directors;
    if (!x || !D) {
      topo_x.resize(3 * N);
      topo_d.resize(9 * N);
      rec->sweep(y, Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, topo_x.data(), topo_d.data());
      x = topo_x.data();
      D = topo_d.data();
    }
    std::vector<double> d1(3 * N);
    for (std::size_t i = 0; i < N; ++i)
      for (int a = 0; a < 3; ++a) d1[3 * i + a] = D[9 * i + 3 * a];
    try {
      const auto r = topology::ribbon_topology(x, d1.data(), N, nullptr, topology::writhe_stride(N), false);
      fr.topology = Frame::Topology{static_cast<double>(r.Lk), r.Tw, r.Wr};
    } catch (const Error&) {  // an unresolved ribbon (or non-finite points): no Lk in this frame
      const double nan = std::numeric_limits<double>::quiet_NaN();
      fr.topology = Frame::Topology{nan, nan, nan};
    }
  }
  if (sc.thermal.on)
    fr.kinetic_kT = rodcore::kinetic_kT(y, N, sc.rod.length / static_cast<double>(N), system->material());
  for (auto& o : observers) o->frame(self, fr);
}

// The guard of the reduction failed at a step that delivers a frame (system.hpp,
// reduction_holds): the run continues on the full system from that step.
void Simulation::Impl::leave_reduction(double ti) {
  const std::vector<double> y_full(system->expand(integ->y().data()),
                                   system->expand(integ->y().data()) + y0.size());
  summary.steps += integ->steps();
  summary.rejected += integ->rejected();
  summary.rhs_evaluations += integ->rhs_evaluations();
  start_integrator(std::nullopt, ti, y_full.data());
  summary.reduce_note = "reduced planar system until t = " + num(ti) +
                        ", then the full system: the RHS of an out-of-plane row was not zero";
}

void Simulation::Impl::advance(const Simulation& self, double t_req) {
  const Scene& sc = scene;
  const int frames = sc.output.frames;
  // Steps aim at the end of the scene (or beyond it, if asked), never at
  // t_req: output times and pieces never shorten a step.
  const double t_stop = std::max(sc.output.t_end, t_req);
  while (integ->t() < t_req) {
    integ->step(t_stop);
    const double ti = integ->t();
    const double* y = integ->y().data();
    const StepView view{ti, N, y, integ->size(), &system->rows()};
    for (auto& o : observers) o->step(self, view);
    const bool frame_due = j < frames && frame_time(j) <= ti;
    const bool fall_back = frame_due && system->planar() && !system->reduction_holds(system->expand(y));
    while (j < frames && frame_time(j) <= ti) {
      const double tj = frame_time(j);
      if (tj == ti) {
        deliver(self, j, tj, system->expand(y));
      } else {
        integ->dense(tj, buf.data());
        deliver(self, j, tj, system->expand(buf.data()));
      }
      ++j;
    }
    if (fall_back) leave_reduction(ti);
    for (auto& o : observers) o->stepped(self);
  }
  // The state at t_req: the step's end, or its continuous extension.
  const double* y_now = integ->y().data();
  if (t_req != integ->t()) {
    integ->dense(t_req, buf.data());
    y_now = buf.data();
  }
  const double* y_full = system->expand(y_now);
  std::copy(y_full, y_full + 12 * N, state.begin());
  t = t_req;
}

void Simulation::step_to(double t) {
  Impl& d = *impl_;
  if (!std::isfinite(t) || t < d.t)
    throw InputError(d.scene.source + ": step_to(t = " + num(t) +
                     "): t must be finite and >= the current time " + num(d.t));
  struct Clock {  // wall time of this call, also when it throws
    Impl& d;
    explicit Clock(Impl& impl) : d(impl) { d.call_start = std::chrono::steady_clock::now(); }
    ~Clock() {
      d.wall_spent = d.wall_seconds() - d.wall_before;
      d.call_start.reset();
    }
  } clock(d);
  try {
    if (!d.started) d.start(*this);
    d.advance(*this, t);
  } catch (const NumericalError& e) {
    for (auto& o : d.observers) o->failed(*this, e.what());
    throw;
  }
}

RunSummary Simulation::summary() const {
  const Impl& d = *impl_;
  RunSummary s = d.summary;
  if (d.integ) {
    s.steps += d.integ->steps();
    s.rejected += d.integ->rejected();
    s.rhs_evaluations += d.integ->rhs_evaluations();
  }
  s.reduced = d.system->planar().has_value();
  s.wall_seconds = d.wall_seconds();
  if (d.passage) s.thermal_note += (s.thermal_note.empty() ? "" : "; ") + d.passage->note();
  return s;
}

RunSummary Simulation::run() {
  Impl& d = *impl_;
  step_to(std::max(d.t, d.frame_time(d.scene.output.frames - 1)));
  const RunSummary s = summary();
  for (auto& o : d.observers) o->finished(*this, s);
  return s;
}

Checkpoint Simulation::run_point() const {
  const Impl& d = *impl_;
  if (!d.integ) throw Error(d.scene.source + ": no checkpoint before the first step");
  Checkpoint c;
  c.method = d.scene.solver.time;
  c.integrator = d.integ->save_state();
  c.next_frame = d.j;
  c.E0 = d.E0;
  c.energy_drift = d.summary.energy_drift;
  c.reduced = d.system->planar() ? planar_name(*d.system->planar()) : "";
  c.wall_seconds = d.wall_seconds();
  return c;
}

std::shared_ptr<FunctionObserver> on_progress(std::function<void(double t, double t_end)> f) {
  auto o = std::make_shared<FunctionObserver>();
  if (f)
    o->on_stepped = [f = std::move(f)](const Simulation& sim) {
      f(sim.integrator_time(), sim.scene().output.t_end);
    };
  return o;
}

}  // namespace rodcore
