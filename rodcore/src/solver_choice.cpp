#include "rodcore/solver_choice.hpp"

#include <cmath>

#include "rodcore/message_number.hpp"
#include "rodcore/operators.hpp"

namespace rodcore {
namespace {

std::string num(double x) { return message_number(x); }

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

std::string resolve_space(Scene& sc, const std::vector<double>& y0) {
  if (sc.solver.space != SpaceMethod::automatic)
    return "solver.space = \"" + to_string(sc.solver.space) + "\" as given";
  if (sc.solver.time == TimeMethod::brownian) {
    // The implicit step solves a banded system: its d/ds must be local.
    sc.solver.space = SpaceMethod::fd4;
    return "fd4 (auto: solver.time = \"brownian\" solves a banded system)";
  }
  if (sc.solver.dealias || sc.rod.points < 5) {
    sc.solver.space = SpaceMethod::spectral;
    return sc.solver.dealias ? "spectral (auto: solver.dealias asks for it)"
                             : "spectral (auto: fd4 needs at least 5 points)";
  }
  if (sc.thermal.on) {
    // A thermal state fills every resolved wavenumber (no smooth content for
    // the test below to see), and the body frame of a twisted rod carries a
    // lab bending mode n at n +- the turns: fd4 puts the 158-bp DNA rod's
    // n = 1..8 bend frequencies 2-16 % low (bench/thermal_space.py).
    sc.solver.space = SpaceMethod::spectral;
    return "spectral (auto: a thermal rod; fd4's bend frequencies of a twisted rod are low, docs/thermal.md)";
  }
  const double tail = spectral_tail(sc, y0);
  sc.solver.space = tail > kSmoothTail ? SpaceMethod::fd4 : SpaceMethod::spectral;
  return to_string(sc.solver.space) + " (auto: high-wavenumber content of the initial fields " + num(tail) +
         (tail > kSmoothTail ? " > " : " <= ") + num(kSmoothTail) +
         (tail > kSmoothTail ? ", non-smooth)" : ", smooth)");
}

std::string resolve_time(Scene& sc) {
  if (sc.solver.time == TimeMethod::automatic && sc.thermal.has_friction()) {
    sc.solver.time = TimeMethod::langevin;
    return "langevin (auto: [thermal] sets a friction)";
  }
  if (sc.solver.time == TimeMethod::automatic) {
    sc.solver.time = TimeMethod::dop853;
    return "dop853 (auto: the fastest at errors <= 1e-6 in the benchmarks)";
  }
  return "solver.time = \"" + to_string(sc.solver.time) + "\" as given";
}

}  // namespace

void resolve_method(Scene& sc, const std::vector<double>& y0, std::string& note) {
  const std::string why_space = resolve_space(sc, y0);
  const std::string why_time = resolve_time(sc);
  note = why_space + "; " + why_time;
}

std::optional<Planar> choose_reduction(const Scene& sc, const MaterialField& mf, const double* y,
                                       std::size_t N, std::string& note) {
  if (sc.solver.reduce == Reduction::off) {
    note = "full system (solver.reduce = \"off\")";
  } else if (sc.thermal.on) {
    note = "full system: a thermal rod is not planar";
  } else if (sc.contact.on) {
    note = "full system: self-contact ([contact]) acts in every direction";
  } else if (!planar_reduction_allowed(sc.rod)) {
    note = "full system: the intrinsic shape is not uniform Gamma0 = (0, 0, G03), Omega0 = 0";
  } else if (mf.kind == MaterialKind::per_point) {
    note = "full system: the reduced planar system is implemented for a uniform material only";
  } else if (const auto p = planar_polarisation(y, N); !p) {
    note = "full system: the initial state is not exactly planar";
  } else if (const std::string why = planar_material_coupling(mf, *p); !why.empty()) {
    note = std::string("full system: the material does not keep the ") + planar_name(*p) +
           " polarisation invariant (" + why + ")";
  } else {
    note = std::string("reduced planar system (") + planar_name(*p) +
           " polarisation, 6 of 12 rows; paper Sec 4.1)";
    return p;
  }
  return std::nullopt;
}

bool reduction_allowed(const Scene& sc, const MaterialField& mf, Planar p) {
  return planar_reduction_allowed(sc.rod) && mf.kind != MaterialKind::per_point &&
         planar_material_coupling(mf, p).empty();
}

}  // namespace rodcore
