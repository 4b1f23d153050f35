// A scene: everything one run needs, already validated. The TOML reader
// (scene_reader.hpp) and the Python module both produce this struct; the
// solver only ever sees a Scene, never a file. See docs/scenes.md.
#pragma once
#include <array>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "rodcore/dna_units.hpp"  // generated from dna_models (the one source of the defaults)
#include "rodcore/state.hpp"

namespace rodcore {

// ---- Choices: a setting that is one of a few values is an enum, never a
// string. Each has one table of spellings, ChoiceNames<E>::all, in the order
// messages list them: scene files, output attributes, messages and the
// Python module all spell the values from it (to_string, from_string), and
// the TOML reader maps a scene's string onto the enum with it. A new value is
// one enumerator and one row of its table.
template <class E>
struct ChoiceNames;  // specialised below for each choice

template <class E>
struct Spelling {
  E value;
  std::string_view name;
};

template <class E>
concept Choice = requires {
  ChoiceNames<E>::all;
};

// solver.space: the spatial derivative (operators.hpp). automatic: chosen by
// Simulation from the initial fields (docs/performance.md).
enum class SpaceMethod { automatic, fd4, spectral };
template <>
struct ChoiceNames<SpaceMethod> {
  static constexpr std::array<Spelling<SpaceMethod>, 3> all{
      {{SpaceMethod::automatic, "auto"}, {SpaceMethod::fd4, "fd4"}, {SpaceMethod::spectral, "spectral"}}};
};

// solver.time: the time integrator (integrators.hpp). automatic: dop853, or
// langevin when [thermal] sets a friction. langevin: the Langevin splitting of
// the thermal rod (thermal.hpp, docs/thermal.md), fixed step solver.dt.
// brownian: the overdamped rod (brownian.hpp), linearly implicit, fixed step solver.dt.
enum class TimeMethod { automatic, rk4, rk4_doubling, dopri5, dop853, langevin, brownian };
template <>
struct ChoiceNames<TimeMethod> {
  static constexpr std::array<Spelling<TimeMethod>, 7> all{{{TimeMethod::automatic, "auto"},
                                                            {TimeMethod::rk4, "rk4"},
                                                            {TimeMethod::rk4_doubling, "rk4-doubling"},
                                                            {TimeMethod::dopri5, "dopri5"},
                                                            {TimeMethod::dop853, "dop853"},
                                                            {TimeMethod::langevin, "langevin"},
                                                            {TimeMethod::brownian, "brownian"}}};
};

// solver.reduce: automatic: the reduced planar system when the scene allows
// it (reduced_planar.hpp); off: always the full system.
enum class Reduction { automatic, off };
template <>
struct ChoiceNames<Reduction> {
  static constexpr std::array<Spelling<Reduction>, 2> all{
      {{Reduction::automatic, "auto"}, {Reduction::off, "off"}}};
};

// initial.kind: the registry of initial conditions (initial_conditions.hpp
// declares each kind's parameters and makes its state).
enum class InitialKind {
  rest,
  twisted_wave,
  untwisted_wave,
  shear_oscillation,
  dna_planar,
  ring_rotating,
  ring_twisting,
  file
};
template <>
struct ChoiceNames<InitialKind> {
  static constexpr std::array<Spelling<InitialKind>, 8> all{
      {{InitialKind::rest, "rest"},
       {InitialKind::twisted_wave, "twisted_wave"},
       {InitialKind::untwisted_wave, "untwisted_wave"},
       {InitialKind::shear_oscillation, "shear_oscillation"},
       {InitialKind::dna_planar, "dna_planar"},
       {InitialKind::ring_rotating, "ring_rotating"},
       {InitialKind::ring_twisting, "ring_twisting"},
       {InitialKind::file, "file"}}};
};

// Is `value` one of the table's (a value cast from a bad integer is not)?
template <Choice E>
constexpr bool is_known(E value) {
  for (const auto& s : ChoiceNames<E>::all)
    if (s.value == value) return true;
  return false;
}

// The spelling of a value, e.g. to_string(TimeMethod::rk4_doubling) == "rk4-doubling".
template <Choice E>
std::string to_string(E value) {
  for (const auto& s : ChoiceNames<E>::all)
    if (s.value == value) return std::string(s.name);
  return "(not a valid value: " + std::to_string(static_cast<int>(value)) + ")";
}

// The value of a spelling, or nothing if it is not one.
template <Choice E>
constexpr std::optional<E> from_string(std::string_view name) {
  for (const auto& s : ChoiceNames<E>::all)
    if (s.name == name) return s.value;
  return std::nullopt;
}

// Every spelling, in table order (for messages and docs).
template <Choice E>
std::vector<std::string> choice_names() {
  std::vector<std::string> out;
  for (const auto& s : ChoiceNames<E>::all) out.emplace_back(s.name);
  return out;
}

// What the code may set a value to, for messages: `key = 7 is not a valid
// value; allowed: "auto", "off"` (a value cast from a bad integer), or "" if
// `value` is one of the table's.
template <Choice E>
std::string invalid_choice(const std::string& key, E value) {
  if (is_known(value)) return {};
  std::string allowed;
  for (const auto& s : ChoiceNames<E>::all)
    allowed += (allowed.empty() ? "\"" : ", \"") + std::string(s.name) + "\"";
  return key + " = " + std::to_string(static_cast<int>(value)) + " is not a valid value; allowed: " + allowed;
}

// The rod's material, dimensionless (Eqs 7-9, 15; docs/numerics.md, "General
// material"). Stored energy W = 1/2 e.K e with e = (Gamma - Gamma0, Omega -
// Omega0), kinetic energy 1/2 rho |gamma|^2 + 1/2 omega.I omega. Three forms,
// the most specific one that is given wins (material.hpp turns any of them
// into the per-kernel form and validates it):
//   * the paper's diagonals C, D, I and rho (default: the paper's DNA);
//   * a uniform 6 x 6 K (rows/cols Gamma1..3, Omega1..3) and/or a 3 x 3 I;
//   * per grid point (material_file): K, I and rho at every point.
struct Material {
  Vec3 C{dna_units::C_star[0], dna_units::C_star[1], dna_units::C_star[2]};
  Vec3 D{dna_units::D_star[0], dna_units::D_star[1], dna_units::D_star[2]};
  Vec3 I{dna_units::I_star[0], dna_units::I_star[1], dna_units::I_star[2]};
  double rho = 1.0;
  std::vector<double> K;       // 36 values row-major (uniform), or empty: diag(C, D)
  std::vector<double> I_full;  // 9 values row-major (uniform), or empty: diag(I)
  // Per grid point, or empty: K_s N*36 ([i*36 + 6 r + c]), I_s N*9, rho_s N.
  std::vector<double> K_s, I_s, rho_s;
  std::string file;             // the material file these came from (for records), or empty
  bool file_has_shape = false;  // the file also gave rod.Gamma0_s / Omega0_s
};

struct Rod {
  double length = 0.0;         // fiducial length L
  int points = 0;              // N grid points, s_i = i L / N, i = 0..N-1 (periodic)
  Vec3 Gamma0{0.0, 0.0, 1.0};  // uniform intrinsic shape ...
  Vec3 Omega0{0.0, 0.0, 0.0};
  // ... or, when non-empty, intrinsic shape varying along s: 3*N values each,
  // laid out component-major like the state ([c*N + i]).
  std::vector<double> Gamma0_s;
  std::vector<double> Omega0_s;
};

// Initial condition: a kind with its parameters. Each kind declares its
// parameters (name, default, allowed range, doc) in initial_conditions.hpp;
// the reader validates against that table, so `numbers` holds every
// parameter of the kind (defaults filled in) and nothing else.
struct Initial {
  InitialKind kind = InitialKind::rest;
  std::map<std::string, double> numbers;
  std::map<std::string, std::string> strings;  // e.g. branch = "plus"
  std::string path;                            // kind = "file": absolute path to HDF5
};

struct SolverOptions {
  SpaceMethod space = SpaceMethod::automatic;  // automatic: resolved by Simulation
  bool dealias = false;                        // spectral only: 2/3-rule filter on the derivative
  TimeMethod time = TimeMethod::automatic;     // automatic: dop853
  double rtol = 1e-10;
  double atol = 1e-10;
  double dt = 1e-2;       // fixed step, or first step of adaptive schemes
  double dt_min = 1e-12;  // adaptive step below this: NumericalError
  long max_steps = 100000000;
  Reduction reduce = Reduction::automatic;  // the reduced planar system when allowed
  // brownian only: the noise that makes the linearised rod's stationary state exact at any dt
  // (false: the plain implicit Euler noise, too cold at lambda dt >> 1: a comparison)
  bool exact_noise = true;
};

struct OutputOptions {
  double t_end = 1.0;
  int frames = 2;                      // equally spaced output times 0..t_end inclusive
  bool internal = true;                // fields/gamma, omega, Gamma, Omega
  bool energy = false;                 // energy (T)
  bool energy_parts = false;           // energy_parts/<name> (T)
  bool centerline = false;             // centerline (T x N x 3)
  bool directors = false;              // directors (T x N x 3 x 3)
  double checkpoint_interval_s = 0.0;  // wall seconds between checkpoints (0: off)
};

struct Checks {
  // Relative energy drift |E - E0| / max(|E0|, tiny) that stops the run.
  double max_energy_drift = std::numeric_limits<double>::infinity();
  double max_director_norm_error = 1e-8;
  bool stop_on_fold = true;  // Gamma3 <= 0 somewhere
};

// [thermal]: the rod at a temperature (docs/thermal.md). Off unless the
// scene has the section; a scene without it runs bit for bit as before.
// Energies in the scene's material units (the rod's energy unit C l for the
// paper's DNA), frictions per unit length in rod units, resolved by the
// scene reader (a "water" friction from viscosity_mPa_s and radius_nm,
// thermal.hpp).
struct Thermal {
  bool on = false;                                                  // the scene has [thermal]
  double kT = 0.0;                                                  // k_B T, >= 0
  double temperature_K = std::numeric_limits<double>::quiet_NaN();  // when the scene gives it
  unsigned long long seed = 1;                                      // key of the random numbers (philox.hpp)
  bool sample_initial = true;                                       // add a Boltzmann sample to [initial]
  std::array<double, 2> friction_translational{0.0, 0.0};           // [along d3, across] per length
  std::array<double, 2> friction_rotational{0.0, 0.0};              // [about d3, across] per length
  bool translational_water = false, rotational_water = false;       // given as "water"
  double viscosity_mPa_s = 0.89;                                    // for "water"
  double radius_nm = 1.0;                                           // for "water"
  // for "water": the length of the motion whose drag the cylinder formulas
  // give (NaN: the rod's length, the wavelength of its slowest mode)
  double friction_length_nm = std::numeric_limits<double>::quiet_NaN();
  // Keep the initial state's closure (the box of a box-held rod, the closed
  // ring): the strains are projected back onto it at the end of the first
  // step that reaches each multiple of closure_interval (time; 0: every
  // step); closure.hpp, docs/thermal.md.
  bool keep_closure = true;
  double closure_interval = 0.5;
  bool has_friction() const {
    return friction_translational[0] > 0.0 || friction_translational[1] > 0.0 ||
           friction_rotational[0] > 0.0 || friction_rotational[1] > 0.0;
  }
};

// [contact]: self-contact, the rod cannot pass through itself (docs/topology.md,
// "Self-contact"; the potential: rodcore/src/rodcore/contact.hpp). Off unless the scene
// has the section. Lengths in rod units, resolved by the scene reader.
struct Contact {
  bool on = false;                                                // the scene has [contact]
  double diameter = 0.0;                                          // effective diameter d
  double diameter_nm = std::numeric_limits<double>::quiet_NaN();  // when the scene gives it in nm
  double barrier_kT = 100.0;                                      // U_perp(0) / kT of a right-angle crossing
  double kT = 0.0;  // the kT of the calibration: thermal.kT if > 0, else k_B 300 K (resolved)
  int stride = 1;   // beads at every stride-th grid point
};

struct Scene {
  std::string source;  // where it came from (file path or "<dict>"), for messages
  Rod rod;
  Material material;
  Initial initial;
  SolverOptions solver;
  OutputOptions output;
  Checks checks;
  Thermal thermal;
  Contact contact;
};

}  // namespace rodcore
