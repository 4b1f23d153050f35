// Bad numbers never pass: NaN in initial fields, folding, CFL violation of
// the fixed-step scheme, step underflow, energy drift beyond the scene's
// bound, unknown names. Frames delivered before the error are complete.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "physics_test_util.hpp"
#include "rodcore/error.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/scene_io.hpp"

using namespace rodcore;
using namespace rodtest;

namespace {
bool message_has(const std::function<void()>& f, const std::string& what) {
  try {
    f();
  } catch (const Error& e) {
    return std::string(e.what()).find(what) != std::string::npos;
  }
  return false;
}
}  // namespace

TEST(PhysicsErrors, NaNInInitialFields) {
  Scene sc = twisted_wave_scene(16, "p", "plus");
  sc.initial.kind = InitialKind::rest;
  sc.initial.numbers.clear();
  sc.initial.strings.clear();
  sc.rod.Gamma0_s.assign(3 * 16, 0.0);
  sc.rod.Omega0_s.assign(3 * 16, 0.0);
  for (int i = 0; i < 16; ++i) sc.rod.Gamma0_s[32 + i] = 1.0;
  sc.rod.Gamma0_s[32 + 5] = std::nan("");
  EXPECT_THROW(Simulation{sc}, InputError);
  sc = twisted_wave_scene(16, "p", "plus");
  sc.initial.numbers["A"] = std::numeric_limits<double>::infinity();
  EXPECT_TRUE(message_has([&] { Simulation s(sc); }, "initial.A"));
}

TEST(PhysicsErrors, FoldStopsTheRunAndKeepsFrames) {
  Scene sc;
  sc.source = "fold.toml";
  sc.rod.length = 1.0;
  sc.rod.points = 8;
  sc.initial.kind = InitialKind::shear_oscillation;
  sc.initial.numbers = {{"omega2", -3.0}, {"Gamma1", 0.8}, {"Gamma3", 0.6}};
  sc.output.t_end = 5.0;
  sc.output.frames = 101;
  int frames = 0;
  bool complete = true;
  Simulation sim(sc);
  try {
    sim.add_observer(on_frame([&](const Frame& f) {
      ++frames;
      complete = complete && f.N == 8 && f.y != nullptr && std::isfinite(f.y[12 * 8 - 1]);
    }));
    sim.run();
    FAIL() << "no fold detected";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("folded"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("fold.toml"), std::string::npos);
  }
  EXPECT_GT(frames, 0);
  EXPECT_TRUE(complete);
  // with the check off the same run goes on
  sc.checks.stop_on_fold = false;
  sc.output.t_end = 0.5;
  EXPECT_NO_THROW(run_scene(sc));
}

TEST(PhysicsErrors, Rk4BeyondCflIsAnError) {
  Scene sc = twisted_wave_scene(64, "p", "plus");
  sc.solver.time = TimeMethod::rk4;
  sc.solver.dt = 0.05;  // spectral: lambda ~ sqrt(1.21*1.67/2)... * pi/h ~ 65 -> dt_max ~ 0.04
  EXPECT_TRUE(message_has([&] { run_scene(sc); }, "stability limit"));
  sc.solver.dt = 0.01;
  sc.output.t_end = 0.1;
  EXPECT_NO_THROW(run_scene(sc));
}

TEST(PhysicsErrors, UnderflowAndDriftAreErrors) {
  Scene sc = twisted_wave_scene(16, "p", "plus");
  sc.solver.dt_min = 0.5;  // the first step (dt = 1e-2) is already below it
  EXPECT_TRUE(message_has([&] { run_scene(sc); }, "underflow"));
  sc = twisted_wave_scene(16, "p", "plus");
  sc.solver.time = TimeMethod::rk4;
  sc.solver.dt = 0.03;
  sc.checks.max_energy_drift = 1e-15;
  sc.output.t_end = 2.0;
  sc.output.frames = 5;
  EXPECT_TRUE(message_has([&] { run_scene(sc); }, "energy drift"));
}

TEST(PhysicsErrors, UnknownNamesListWhatIsAllowed) {
  // The method and the kind are enums: a scene built in code cannot name an
  // unknown one, a file can (the reader lists the allowed spellings), and a
  // value cast from a bad integer is refused with the same list.
  EXPECT_TRUE(
      message_has([] { read_scene_string("[rod]\nlength = 1\npoints = 8\n[solver]\nspace = \"fd2\"\n"); },
                  "allowed: one of \"auto\", \"fd4\", \"spectral\""));
  EXPECT_TRUE(
      message_has([] { read_scene_string("[rod]\nlength = 1\npoints = 8\n[solver]\ntime = \"euler\"\n"); },
                  "\"rk4-doubling\", \"dopri5\", \"dop853\""));
  EXPECT_TRUE(
      message_has([] { read_scene_string("[rod]\nlength = 1\npoints = 8\n[initial]\nkind = \"wave\"\n"); },
                  "\"twisted_wave\""));
  Scene sc = twisted_wave_scene(16, "p", "plus");
  sc.solver.space = static_cast<SpaceMethod>(7);
  EXPECT_TRUE(message_has([&] { Simulation s(sc); },
                          "solver.space = 7 is not a valid value; allowed: \"auto\", \"fd4\", \"spectral\""));
  sc = twisted_wave_scene(16, "p", "plus");
  sc.solver.time = static_cast<TimeMethod>(7);
  EXPECT_TRUE(message_has([&] { Simulation s(sc); }, "\"dop853\""));
  sc = twisted_wave_scene(16, "p", "plus");
  sc.initial.kind = static_cast<InitialKind>(70);
  EXPECT_TRUE(message_has([&] { Simulation s(sc); }, "\"twisted_wave\""));
  sc = twisted_wave_scene(16, "x", "plus");
  EXPECT_TRUE(message_has([&] { Simulation s(sc); }, "allowed: \"p\", \"m\""));
  sc = twisted_wave_scene(16, "p", "plus");
  sc.rod.Omega0 = {0.1, 0.0, 1.0};
  EXPECT_TRUE(message_has([&] { Simulation s(sc); }, "rod.Omega0"));
}

TEST(PhysicsErrors, RegistryDeclaresEveryKind) {
  // One registry entry per enumerator, in the order of its spellings.
  const auto& all = ChoiceNames<InitialKind>::all;
  ASSERT_EQ(initial_kinds().size(), all.size());
  for (std::size_t i = 0; i < all.size(); ++i) {
    const auto& kind = initial_kinds()[i];
    EXPECT_EQ(kind.kind, all[i].value) << i;
    EXPECT_EQ(kind.name, all[i].name);
    EXPECT_EQ(&initial_kind_spec(all[i].value), &kind);
    EXPECT_FALSE(kind.doc.empty()) << kind.name;
    for (const auto& p : kind.numbers) {
      EXPECT_FALSE(p.doc.empty()) << kind.name << "." << p.name;
      EXPECT_LE(p.min, p.max);
    }
  }
}

TEST(PhysicsErrors, NonPeriodicTranslationIsRejected) {
  // a twisted rod whose twist does not close over L cannot translate
  // sideways periodically; along its axis it can
  Scene sc;
  sc.source = "<test>";
  sc.rod.length = 5.0;
  sc.rod.points = 16;
  sc.rod.Omega0 = {0.0, 0.0, 1.0};
  sc.initial.numbers = {{"v1", 0.3}};
  EXPECT_TRUE(message_has([&] { Simulation s(sc); }, "not periodic"));
  sc.initial.numbers = {{"v3", 0.3}};
  EXPECT_NO_THROW(Simulation{sc});
}
