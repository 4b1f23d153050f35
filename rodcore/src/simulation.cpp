#include "rodcore/simulation.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>

#include "rodcore/brownian.hpp"
#include "rodcore/closure.hpp"
#include "rodcore/contact.hpp"
#include "rodcore/diagnostics.hpp"
#include "rodcore/error.hpp"
#include "rodcore/guards.hpp"
#include "rodcore/integrators.hpp"
#include "rodcore/message_number.hpp"
#include "rodcore/material.hpp"
#include "rodcore/operators.hpp"
#include "rodcore/reconstruction.hpp"
#include "rodcore/reduced_planar.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/stability.hpp"
#include "rodcore/thermal.hpp"
#include "rodcore/topology.hpp"

namespace rodcore {
namespace {

std::string num(double x) { return message_number(x); }

const char* planar_name(Planar p) { return p == Planar::omega2 ? "omega2" : "omega1"; }

// Relative high-wavenumber content of the initial fields: |D f - D_2/3 f| /
// |D f| over all 12 rows, D the spectral derivative and D_2/3 the same with
// the top third of the modes removed. Round-off (~1e-15) for smooth
// (analytic) fields; O(N^-1/2) or more for a jump or grid-scale noise.
double spectral_tail(const Scene& sc, const std::vector<double>& y) {
  const std::size_t N = static_cast<std::size_t>(sc.rod.points);
  const auto full = make_derivative_operator(SpaceMethod::spectral, N, sc.rod.length, false);
  const auto cut = make_derivative_operator(SpaceMethod::spectral, N, sc.rod.length, true);
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

// The closure projection of a thermal run (closure.hpp; docs/thermal.md,
// "Closure in a run"): two chord-Newton steps (one checked), on sweeps of at
// most 0.2 rad per Magnus substep, whose holonomy is within ~1e-4 of the
// output's (0.05 rad) for the 158-bp DNA rod at 300 K; at 4x fewer substeps.
constexpr int kClosureSteps = 2;
constexpr double kClosureTurn = 0.2;
// The overdamped rod's steps are few and long (100 ps for the kilobase ring) and each moves
// the closure of a ring of many persistence lengths far outside the chord steps' reach: up
// to 6 Newton steps, re-linearised, to 1e-10 (each a sweep, O(N), against the step's solve).
constexpr int kBrownianClosureSteps = 6;
constexpr double kBrownianClosureTolerance = 1e-10;

// solver.space / solver.time = automatic -> the measured default
// (docs/performance.md, "Default method rule"); `note` says what and why.
void resolve_method(Scene& sc, const std::vector<double>& y0, std::string& note) {
  std::string why_space = "solver.space = \"" + to_string(sc.solver.space) + "\" as given";
  if (sc.solver.space == SpaceMethod::automatic) {
    if (sc.solver.time == TimeMethod::brownian) {
      // The implicit step solves a banded system: its d/ds must be local.
      sc.solver.space = SpaceMethod::fd4;
      why_space = "fd4 (auto: solver.time = \"brownian\" solves a banded system)";
    } else if (sc.solver.dealias || sc.rod.points < 5) {
      sc.solver.space = SpaceMethod::spectral;
      why_space = sc.solver.dealias ? "spectral (auto: solver.dealias asks for it)"
                                    : "spectral (auto: fd4 needs at least 5 points)";
    } else if (sc.thermal.on) {
      // A thermal state fills every resolved wavenumber (no smooth content for
      // the test below to see), and the body frame of a twisted rod carries a
      // lab bending mode n at n +- the turns: fd4 puts the 158-bp DNA rod's
      // n = 1..8 bend frequencies 2-16 % low (bench/thermal_space.py).
      sc.solver.space = SpaceMethod::spectral;
      why_space = "spectral (auto: a thermal rod; fd4's bend frequencies of a twisted rod are low, "
                  "docs/thermal.md)";
    } else {
      const double tail = spectral_tail(sc, y0);
      sc.solver.space = tail > kSmoothTail ? SpaceMethod::fd4 : SpaceMethod::spectral;
      why_space = to_string(sc.solver.space) + " (auto: high-wavenumber content of the initial fields " +
                  num(tail) + (tail > kSmoothTail ? " > " : " <= ") + num(kSmoothTail) +
                  (tail > kSmoothTail ? ", non-smooth)" : ", smooth)");
    }
  }
  std::string why_time = "solver.time = \"" + to_string(sc.solver.time) + "\" as given";
  if (sc.solver.time == TimeMethod::automatic && sc.thermal.has_friction()) {
    sc.solver.time = TimeMethod::langevin;
    why_time = "langevin (auto: [thermal] sets a friction)";
  } else if (sc.solver.time == TimeMethod::automatic) {
    sc.solver.time = TimeMethod::dop853;
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
  bool reconstruct = false;   // centerline or directors are output
  bool anchor = false;        // the frame at s = 0 is integrated (reconstruct, or closure kept)
  std::vector<double> y0;     // 12 N (+ 7: anchor q(0,t), r(0,t))
  std::vector<double> state;  // 12 N at time t
  double t = 0.0;
  std::vector<double> s;
  std::optional<Checkpoint> resume;
  // Reduced planar system (solver.reduce = "auto", reduced_planar.hpp):
  // the polarisation the initial state lies in, exactly, and why (not).
  std::optional<Planar> planar;
  std::string reduce_note;
  Scene given;              // the scene as given ("auto" kept): what checkpoints record
  std::string method_note;  // how the method was chosen
  std::vector<std::shared_ptr<Observer>> observers;  // the scene's checks first
  std::string thermal_note;                          // what the thermal sample did
  std::unique_ptr<LangevinBath> bath;                // solver.time = "langevin"
  std::unique_ptr<BrownianStep> brownian;            // solver.time = "brownian"
  // A ring (topology.hpp is_closed on the initial centreline): its frames carry Lk, Tw,
  // Wr. With [contact], the self-contact forces, in every RHS evaluation.
  bool closed = false;
  std::unique_ptr<SelfContact> contact;
  // thermal.keep_closure: the box motion T (lab) of the initial state,
  // restored every thermal.closure_interval (closure.hpp).
  std::unique_ptr<ClosureProjector> closure;
  RigidMotion box;

  // ---- the run, set up by start() on the first step_to()/run()
  bool started = false;
  std::optional<Planar> planar_run;  // the system integrated now
  std::unique_ptr<PlanarRHS> planar_rhs;
  std::vector<int> rows;  // integrated rows -> state rows
  OdeSystem sys;
  IntegratorOptions io;
  std::unique_ptr<TimeIntegrator> integ;
  std::vector<double> full, buf, centerline, directors, f_guard;
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

  // Largest characteristic speed (material.hpp), at least 1 as before.
  double wave_speed() const { return std::max(1.0, max_wave_speed(rhs->material_field())); }

  double frame_time(int k) const {
    const int frames = scene.output.frames;
    const double t_end = scene.output.t_end;
    return (k == frames - 1 || frames == 1)
               ? (k == 0 && frames == 1 ? 0.0 : t_end)
               : t_end * static_cast<double>(k) / static_cast<double>(frames - 1);
  }

  // The integrated system: the full 12 rows, or only the 6 rows of a planar
  // polarisation (PlanarRHS evaluates the same RodRHS). `rows` maps the
  // integrated rows to state rows; the 7 anchor values follow in both cases.
  void make_system() {
    planar_rhs.reset();
    rows.clear();
    if (planar_run) {
      planar_rhs = std::make_unique<PlanarRHS>(*rhs, *planar_run);
      rows.assign(planar_rhs->rows().begin(), planar_rhs->rows().end());
    } else {
      for (int r = 0; r < 12; ++r) rows.push_back(r);
    }
    const std::size_t nrows = rows.size();
    const bool recon = anchor;
    sys.n = nrows * N + (recon ? 7 : 0);
    sys.ou = nullptr;
    sys.project = nullptr;
    if (closure) {  // a thermal rod: never reduced, so y is the 12 N state and the anchor
      ClosureProjector* c = closure.get();
      const RigidMotion T = box;
      const double every = scene.thermal.closure_interval;
      const std::size_t at_anchor = 12 * N;
      // At the end of the first step that reaches each multiple of the
      // interval (every step for 0): a function of the step's times only,
      // so a resumed run projects where the uninterrupted one did. "Reaches"
      // to 1e-9 of the interval: a fixed step's accumulated time lands a few
      // ulps short of the multiple it stands for (and a frame there).
      const bool newton = static_cast<bool>(brownian);
      sys.project = [c, T, every, at_anchor, newton](double t_prev, double t, double* y) {
        auto index = [every](double time) { return std::floor(time / every + 1e-9); };
        if (every > 0.0 && index(t) == index(t_prev)) return false;
        const RigidMotion g0{{y[at_anchor], y[at_anchor + 1], y[at_anchor + 2], y[at_anchor + 3]},
                             {y[at_anchor + 4], y[at_anchor + 5], y[at_anchor + 6]}};
        return (newton ? c->project(y, holonomy_for(T, g0), kBrownianClosureSteps, kBrownianClosureTolerance,
                                    true)
                       : c->project(y, holonomy_for(T, g0), kClosureSteps))
                   .steps > 0;
      };
    }
    if (brownian) {
      BrownianStep* b = brownian.get();
      const std::size_t at_anchor = 12 * N;
      sys.brownian = [b, recon, at_anchor](long step, double* y) {
        b->apply(step, y, recon ? y + at_anchor : nullptr);
      };
    }
    if (bath) {
      const LangevinBath* b = bath.get();
      const std::size_t at_anchor = 12 * N;
      sys.ou = [b, recon, at_anchor](long step, double* y) {
        b->apply(step, y);
        // The anchor's quaternion back on the unit sphere (the RK4 part keeps it there only to O(dt^5)).
        if (recon) {
          const Quat q =
              quat_normalized({y[at_anchor], y[at_anchor + 1], y[at_anchor + 2], y[at_anchor + 3]});
          for (int k = 0; k < 4; ++k) y[at_anchor + k] = q[k];
        }
      };
    }
    // Rows of omega and gamma in the integrated state (-1: identically zero).
    std::array<int, 6> at{-1, -1, -1, -1, -1, -1};
    for (std::size_t k = 0; k < nrows; ++k)
      if (rows[k] < 6) at[rows[k]] = static_cast<int>(k);
    RodRHS* r = rhs.get();
    PlanarRHS* pr = planar_rhs.get();
    SelfContact* ct = contact.get();
    const std::size_t n = N;
    sys.f = [r, pr, ct, n, nrows, recon, at](double, const double* y, double* f) {
      if (pr) (*pr)(y, f);
      else (*r)(y, f);
      if (ct) ct->add_to_rhs(y, r->material_field(), f);
      if (recon) {
        auto v = [&](int k) { return at[k] < 0 ? 0.0 : y[at[k] * n]; };
        const Vec3 w0{v(3), v(4), v(5)};
        const Vec3 g0{v(0), v(1), v(2)};
        anchor_rate(y + nrows * n, w0, g0, f + nrows * n);
      }
    };
  }

  // Integrated state -> full state (12 N + anchor), in `full` when reduced.
  const double* expand(const double* y) {
    if (!planar_rhs) return y;
    planar_rhs->expand(y, full.data());
    std::copy(y + 6 * N, y + 6 * N + (anchor ? 7 : 0), full.data() + 12 * N);
    return full.data();
  }

  // Guard of the reduction, at steps that deliver a frame: the full RHS at
  // the (expanded) state must leave the six skipped rows exactly zero. It
  // always does in exact and in floating-point arithmetic (every term feeding
  // them is a product with a zero), so this only catches the impossible; if
  // it ever fails the run continues on the full system from that step.
  bool planar_guard_holds(const double* y12) {
    f_guard.resize(12 * N);
    (*rhs)(y12, f_guard.data());
    for (int r : planar_zero_rows(*planar_run))
      for (std::size_t i = 0; i < N; ++i)
        if (f_guard[r * N + i] != 0.0) return false;
    return true;
  }

  // The energy and its parts of a state (12 N), self-contact included.
  EnergyParts parts(const double* y) const {
    EnergyParts e = rodcore::energy_parts(y, N, scene.rod.length / static_cast<double>(N),
                                          rhs->material_field(), rhs->Gamma0(), rhs->Omega0());
    if (contact) {
      e.contact = contact->energy(y);
      e.has_contact = true;
    }
    return e;
  }

  void start(const Simulation& self);
  void deliver(const Simulation& self, int index, double t, const double* y);
  void advance(const Simulation& self, double t_req);
};

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
  d.op = make_derivative_operator(sc.solver.space, d.N, sc.rod.length, sc.solver.dealias);
  d.rhs = std::make_unique<RodRHS>(sc.rod, sc.material, *d.op);
  d.reconstruct = sc.output.centerline || sc.output.directors;
  d.rec = std::make_unique<Reconstructor>(d.N, sc.rod.length);
  d.s.resize(d.N);
  for (std::size_t i = 0; i < d.N; ++i)
    d.s[i] = static_cast<double>(i) * sc.rod.length / static_cast<double>(d.N);

  d.state = std::move(initial.y);
  check_initial_finite(sc, d.state, d.s);
  // thermal.keep_closure holds the box of the [initial] state, taken before the sample is
  // added: where the sampler's closure stays at linear order its sample is off the box by
  // that gap (0.91 L seen on the 158-bp rod at 300 K), and a run holding the sample's own
  // box would lose its slack tension (docs/thermal.md, "Closure in a run"). The sample itself
  // is left as drawn (its statistics are the sampler's; tests/python/test_thermal_sampler.py).
  const RigidMotion g0{initial.q0, initial.r0};
  if (sc.thermal.on && sc.thermal.keep_closure) {
    d.closure = std::make_unique<ClosureProjector>(d.N, sc.rod.length, d.rhs->material_field(), kClosureTurn);
    d.box = box_motion(d.closure->holonomy(d.state.data()), g0);
  }
  if (sc.thermal.on) {
    if (sc.thermal.sample_initial) {
      d.thermal_note =
          add_thermal_sample(d.state, sc.rod.length, d.rhs->material_field(), sc.thermal.kT, sc.thermal.seed)
              .note;
    } else {
      d.thermal_note = "no thermal sample (thermal.sample_initial = false)";
    }
    if (sc.solver.time == TimeMethod::brownian) {
      // No inertia: the velocities are not variables of the overdamped rod (its
      // output's gamma and omega are zero, its energy the potential energy).
      std::fill(d.state.begin(), d.state.begin() + 6 * static_cast<long>(d.N), 0.0);
      d.thermal_note += "; overdamped (Brownian) rod at kT = " + num(sc.thermal.kT) +
                        ", friction translational [along, across] = [" +
                        num(sc.thermal.friction_translational[0]) + ", " +
                        num(sc.thermal.friction_translational[1]) + "], rotational [about, across] = [" +
                        num(sc.thermal.friction_rotational[0]) + ", " +
                        num(sc.thermal.friction_rotational[1]) + "] per length";
    }
    if (sc.solver.time == TimeMethod::langevin)
      d.thermal_note +=
          "; Langevin rod at kT = " + num(sc.thermal.kT) + ", friction translational [along, across] = [" +
          num(sc.thermal.friction_translational[0]) + ", " + num(sc.thermal.friction_translational[1]) +
          "], rotational [about, across] = [" + num(sc.thermal.friction_rotational[0]) + ", " +
          num(sc.thermal.friction_rotational[1]) + "] per length";
  }
  // A ring or a box-periodic rod, from the initial centreline (the frame at s = 0 does
  // not matter): rings get Lk, Tw, Wr in every frame.
  {
    std::vector<double> x(3 * d.N);
    const auto end =
        d.rec->sweep(d.state.data(), Quat{1.0, 0.0, 0.0, 0.0}, Vec3{0.0, 0.0, 0.0}, x.data(), nullptr);
    d.closed = topology::is_closed(x.data(), d.N);
    if (sc.contact.on) {
      const ContactPotential p = contact_potential(sc.contact);  // the reader checked its keys
      const double period = std::sqrt(end.r[0] * end.r[0] + end.r[1] * end.r[1] + end.r[2] * end.r[2]);
      if (!d.closed && period < 2.0 * p.cutoff)
        throw InputError(
            sc.source + ": [contact]: the box-periodic rod's period " + num(period) +
            " is shorter than twice the contact cut-off " + num(p.cutoff) +
            " (from contact.diameter and contact.barrier_kT): the rod would touch its own images");
      try {
        d.contact = std::make_unique<SelfContact>(d.N, sc.rod.length, p, d.closed);
      } catch (const InputError& e) {
        throw InputError(sc.source + ": " + e.what());
      }
    }
  }
  if (d.closure) {
    // A sample that left the box (its closure at linear order only) is brought back by the
    // run's projections: each re-linearises at the current state (a few intervals).
    const double gap = d.closure->size(
        ClosureProjector::defect(d.closure->holonomy(d.state.data()), holonomy_for(d.box, g0)));
    if (gap > 1e-3)
      d.thermal_note +=
          "; the sample is off the initial state's box by " + num(gap) + ": the projections bring it back";
    d.thermal_note +=
        "; closure (the box motion of the initial state) restored " +
        (sc.thermal.closure_interval > 0.0 ? "every " + num(sc.thermal.closure_interval) + " time units"
                                           : std::string("every step")) +
        " by the least strain change in the energy metric";
  }
  d.anchor = d.reconstruct || d.closure;
  d.y0 = d.state;
  if (d.anchor) {
    d.y0.insert(d.y0.end(), initial.q0.begin(), initial.q0.end());
    d.y0.insert(d.y0.end(), initial.r0.begin(), initial.r0.end());
  }
  if (sc.solver.reduce == Reduction::off) {
    d.reduce_note = "full system (solver.reduce = \"off\")";
  } else if (sc.thermal.on) {
    d.reduce_note = "full system: a thermal rod is not planar";
  } else if (sc.contact.on) {
    d.reduce_note = "full system: self-contact ([contact]) acts in every direction";
  } else if (!planar_reduction_allowed(sc.rod)) {
    d.reduce_note = "full system: the intrinsic shape is not uniform Gamma0 = (0, 0, G03), Omega0 = 0";
  } else if (d.rhs->material_field().kind == MaterialKind::per_point) {
    d.reduce_note = "full system: the reduced planar system is implemented for a uniform material only";
  } else if (const auto p = planar_polarisation(d.state.data(), d.N); !p) {
    d.reduce_note = "full system: the initial state is not exactly planar";
  } else if (const std::string why = planar_material_coupling(d.rhs->material_field(), *p); !why.empty()) {
    d.reduce_note = std::string("full system: the material does not keep the ") + planar_name(*p) +
                    " polarisation invariant (" + why + ")";
  } else {
    d.planar = p;
    d.reduce_note = std::string("reduced planar system (") + planar_name(*d.planar) +
                    " polarisation, 6 of 12 rows; paper Sec 4.1)";
  }
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
  if (!c.reduced.empty() &&
      (!planar_reduction_allowed(d.scene.rod) || d.rhs->material_field().kind == MaterialKind::per_point ||
       !planar_material_coupling(d.rhs->material_field(),
                                 c.reduced == "omega2" ? Planar::omega2 : Planar::omega1)
            .empty()))
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
                             d.rhs->material_field());
}

double Simulation::energy() const { return impl_->parts(impl_->state.data()).total(); }

std::map<std::string, double> Simulation::energy_parts() const {
  return impl_->parts(impl_->state.data()).as_map();
}

void Simulation::rhs(const double* y, double* dydt) const {
  const Impl& d = *impl_;
  (*d.rhs)(y, dydt);
  if (d.contact) d.contact->add_to_rhs(y, d.rhs->material_field(), dydt);
}

void Simulation::Impl::start(const Simulation& self) {
  const Scene& sc = scene;
  started = true;
  summary.method = op->name() + "+" + to_string(sc.solver.time);

  // Explicit fixed step: RK4 is stable on the imaginary axis up to
  // |lambda dt| = 2 sqrt 2 ~ 2.83; we allow 2.8 (1 % margin). For a uniform
  // intrinsic shape and a uniform material (any K, I, rho) lambda is exact:
  // the spectral radius of the system linearised about the rest state over
  // every wavenumber the operator resolves (stability.hpp). For an s-varying
  // shape or a per-point material only the estimate c_max k_max is available
  // (c_max the largest characteristic speed over the points, material.hpp; it
  // leaves out the lower-order terms, which raised the true radius by up to
  // 1.6x on the DNA rod).
  if (sc.solver.time == TimeMethod::rk4 || sc.solver.time == TimeMethod::langevin) {
    const bool uniform = sc.rod.Gamma0_s.empty() && sc.rod.Omega0_s.empty() &&
                         rhs->material_field().kind != MaterialKind::per_point;
    const double lambda = uniform ? linear_spectral_radius(*rhs) : wave_speed() * op->max_wavenumber();
    const double dt_cfl = 2.8 / lambda;
    if (sc.solver.dt > dt_cfl)
      throw NumericalError(sc.source + ": solver.dt = " + num(sc.solver.dt) +
                           " exceeds the RK4 stability limit " + num(dt_cfl) +
                           (uniform ? " (2.8 / spectral radius " + num(lambda) +
                                          " of the equations linearised about the rest state, "
                                    : " (estimate: 2.8 / (max wave speed " + num(wave_speed()) +
                                          " x max wavenumber " + num(op->max_wavenumber()) + "), ") +
                           op->name() + "); use solver.dt <= " + num(dt_cfl * (1.0 - 5e-6)) +
                           (sc.solver.time == TimeMethod::rk4
                                ? ", fewer rod.points, or an adaptive solver.time"
                                : " or fewer rod.points"));
  }
  if (sc.solver.time == TimeMethod::langevin)
    bath = std::make_unique<LangevinBath>(rhs->material_field(), sc.rod.length / static_cast<double>(N),
                                          sc.thermal.kT, sc.thermal.friction_translational,
                                          sc.thermal.friction_rotational, sc.solver.dt, sc.thermal.seed);

  if (sc.solver.time == TimeMethod::brownian) {
    RodRHS* r = rhs.get();
    SelfContact* ct = contact.get();
    brownian = std::make_unique<BrownianStep>(
        N, sc.rod.length, rhs->material_field(), *op,
        [r, ct](const double* y, double* f) {
          (*r)(y, f);
          if (ct) ct->add_to_rhs(y, r->material_field(), f);
        },
        sc.thermal.friction_translational, sc.thermal.friction_rotational, sc.thermal.kT, sc.solver.dt,
        sc.thermal.seed,
        sc.solver.exact_noise ? BrownianStep::Noise::exact : BrownianStep::Noise::implicit_euler);
  }

  planar_run = planar;
  if (resume)
    planar_run = resume->reduced.empty()
                     ? std::nullopt
                     : std::optional<Planar>(resume->reduced == "omega2" ? Planar::omega2 : Planar::omega1);
  summary.reduce_note = reduce_note;
  summary.method_note = method_note;
  summary.thermal_note = thermal_note;
  if (resume && planar_run != planar)
    summary.reduce_note = planar_run
                              ? "reduced planar system (as in the checkpoint)"
                              : "full system (as in the checkpoint: the run had left the reduced system)";
  make_system();
  full.assign(y0.size(), 0.0);
  io.rtol = sc.solver.rtol;
  io.atol = sc.solver.atol;
  io.dt = sc.solver.dt;
  io.dt_min = sc.solver.dt_min;
  io.max_steps = sc.solver.max_steps;
  io.norm_size = y0.size();  // the skipped rows count as the zeros they are
  integ = make_time_integrator(sc.solver.time, sys, io);
  if (resume) {
    integ->restore_state(resume->integrator);
    wall_before = resume->wall_seconds;
    summary.energy_drift = resume->energy_drift;
  } else if (planar_rhs) {
    std::vector<double> y0r(sys.n);
    planar_rhs->reduce(y0.data(), y0r.data());
    std::copy(y0.begin() + 12 * N, y0.end(), y0r.begin() + 6 * N);
    integ->reset(0.0, y0r.data());
  } else {
    integ->reset(0.0, y0.data());
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
    deliver(self, 0, 0.0, expand(integ->y().data()));
    while (j < sc.output.frames && sc.output.t_end == 0.0) deliver(self, j++, 0.0, expand(integ->y().data()));
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
    const EnergyParts e = parts(y);
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
    fr.kinetic_kT = rodcore::kinetic_kT(y, N, sc.rod.length / static_cast<double>(N), rhs->material_field());
  for (auto& o : observers) o->frame(self, fr);
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
    const StepView view{ti, N, y, sys.n, &rows};
    for (auto& o : observers) o->step(self, view);
    const bool frame_due = j < frames && frame_time(j) <= ti;
    bool fall_back = false;
    if (frame_due && planar_rhs) fall_back = !planar_guard_holds(expand(y));
    while (j < frames && frame_time(j) <= ti) {
      const double tj = frame_time(j);
      if (tj == ti) {
        deliver(self, j, tj, expand(y));
      } else {
        integ->dense(tj, buf.data());
        deliver(self, j, tj, expand(buf.data()));
      }
      ++j;
    }
    if (fall_back) {
      const std::vector<double> y_full(expand(y), expand(y) + y0.size());
      const long steps = integ->steps(), rejected = integ->rejected(), evals = integ->rhs_evaluations();
      planar_run.reset();
      make_system();
      integ = make_time_integrator(sc.solver.time, sys, io);
      integ->reset(ti, y_full.data());
      summary.steps += steps;
      summary.rejected += rejected;
      summary.rhs_evaluations += evals;
      summary.reduce_note = "reduced planar system until t = " + num(ti) +
                            ", then the full system: the RHS of an out-of-plane row was not zero";
    }
    for (auto& o : observers) o->stepped(self);
  }
  // The state at t_req: the step's end, or its continuous extension.
  const double* y_now = integ->y().data();
  if (t_req != integ->t()) {
    integ->dense(t_req, buf.data());
    y_now = buf.data();
  }
  const double* y_full = expand(y_now);
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
  s.reduced = d.planar_run.has_value();
  s.wall_seconds = d.wall_seconds();
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
  c.reduced = d.planar_run ? planar_name(*d.planar_run) : "";
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
