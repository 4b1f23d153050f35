// Simulation with solver.reduce = "auto" (the reduced planar system wired
// into the run) against the same scene with solver.reduce = "off".
// Independent truth: the planar set is invariant (paper Sec 4.1), so the full
// system keeps the six out-of-plane rows exactly zero and does, row for row,
// the same arithmetic on the kept rows; with the error norm counting the
// skipped rows as the zeros they are, even the adaptive schemes take the same
// steps. So every frame (fields, energy, centerline, directors) must agree
// to 1e-12, for every integrator, and a resumed reduced run must equal the
// uninterrupted one bit for bit.
#include <gtest/gtest.h>

#include <filesystem>
#include <numbers>
#include <optional>

#include "physics_test_util.hpp"
#include "rodcore/checkpoint.hpp"
#include "rodcore/reduced_planar.hpp"
#include "rodcore/simulation.hpp"

namespace {

using namespace rodcore;
using rodtest::max_abs_diff;
using rodtest::run_scene;

// The paper's Sec 5.2 untwisted wave (large amplitude), with every output.
Scene untwisted_scene(const std::string& time, const std::string& reduce) {
  Scene sc;
  sc.source = "<test>";
  sc.rod.length = 2.0 * std::numbers::pi;
  sc.rod.points = 32;
  sc.rod.Gamma0 = {0.0, 0.0, 1.0};
  sc.rod.Omega0 = {0.0, 0.0, 0.0};
  sc.initial.kind = InitialKind::untwisted_wave;
  sc.initial.numbers = {{"mode", 2.0}, {"epsilon", 0.3}};
  sc.solver.time = *from_string<TimeMethod>(time);
  sc.solver.dt = 0.01;
  sc.solver.rtol = sc.solver.atol = 1e-9;
  sc.solver.reduce = *from_string<Reduction>(reduce);
  sc.output.t_end = 2.0;
  sc.output.frames = 7;
  sc.output.energy = sc.output.energy_parts = true;
  sc.output.centerline = sc.output.directors = true;
  return sc;
}

void expect_same_runs(const rodtest::RunResult& a, const rodtest::RunResult& b) {
  ASSERT_EQ(a.y.size(), b.y.size());
  for (std::size_t j = 0; j < a.y.size(); ++j) {
    EXPECT_EQ(a.t[j], b.t[j]);
    EXPECT_LE(max_abs_diff(a.y[j], b.y[j]), 1e-12) << "frame " << j;
    EXPECT_LE(std::abs(a.energy[j] - b.energy[j]), 1e-12) << "frame " << j;
    EXPECT_LE(max_abs_diff(a.centerline[j], b.centerline[j]), 1e-12) << "frame " << j;
    EXPECT_LE(max_abs_diff(a.directors[j], b.directors[j]), 1e-12) << "frame " << j;
  }
  EXPECT_EQ(a.summary.steps, b.summary.steps);
  EXPECT_EQ(a.summary.rejected, b.summary.rejected);
}

class ReducedRun : public ::testing::TestWithParam<const char*> {};

TEST_P(ReducedRun, EqualsTheFullSystemForEveryIntegrator) {
  const auto full = run_scene(untwisted_scene(GetParam(), "off"));
  const auto red = run_scene(untwisted_scene(GetParam(), "auto"));
  EXPECT_FALSE(full.summary.reduced);
  EXPECT_TRUE(red.summary.reduced);
  EXPECT_NE(red.summary.reduce_note.find("omega2 polarisation"), std::string::npos)
      << red.summary.reduce_note;
  expect_same_runs(full, red);
  // The full run really kept the out-of-plane rows at zero (the invariance
  // the reduction relies on), and it moved: not a trivial comparison.
  for (const auto& y : full.y) EXPECT_TRUE(in_planar_subspace(y.data(), 32));
  EXPECT_GT(max_abs_diff(full.y.front(), full.y.back()), 0.1);
}

INSTANTIATE_TEST_SUITE_P(AllIntegrators, ReducedRun,
                         ::testing::Values("rk4", "rk4-doubling", "dopri5", "dop853"));

TEST(ReducedRun, OtherPolarisationIsReducedToo) {
  // A lab translation along d2 of a straight untwisted rod: gamma2 only.
  Scene sc = untwisted_scene("dop853", "auto");
  sc.initial.kind = InitialKind::rest;
  sc.initial.numbers = {{"v2", 0.3}};
  const auto red = run_scene(sc);
  EXPECT_TRUE(red.summary.reduced);
  EXPECT_NE(red.summary.reduce_note.find("omega1 polarisation"), std::string::npos)
      << red.summary.reduce_note;
  sc.solver.reduce = Reduction::off;
  expect_same_runs(run_scene(sc), red);
}

TEST(ReducedRun, TinyOutOfPlaneComponentIsNotReduced) {
  // Detection uses exact zeros: gamma1 and gamma2 both non-zero is in
  // neither polarisation, however small gamma2 is.
  Scene sc = untwisted_scene("dop853", "auto");
  sc.initial.kind = InitialKind::rest;
  sc.initial.numbers = {{"v1", 0.3}, {"v2", 1e-300}};
  const auto r = run_scene(sc);
  EXPECT_FALSE(r.summary.reduced);
  EXPECT_NE(r.summary.reduce_note.find("not exactly planar"), std::string::npos) << r.summary.reduce_note;
  // A twisted rod is never reduced, whatever its state.
  Scene tw = rodtest::twisted_wave_scene(16, "p", "plus");
  tw.output.t_end = 0.1;
  const auto t = run_scene(tw);
  EXPECT_FALSE(t.summary.reduced);
  EXPECT_NE(t.summary.reduce_note.find("intrinsic shape"), std::string::npos) << t.summary.reduce_note;
}

TEST(ReducedRun, ResumeFromACheckpointIsExact) {
  const Scene sc = untwisted_scene("dop853", "auto");
  const auto whole = run_scene(sc);
  ASSERT_TRUE(whole.summary.reduced);

  // Checkpoint after the 5th step, through the file (the attribute round trip).
  const std::string path = (std::filesystem::temp_directory_path() / "rodcore_reduced_run.ckpt").string();
  {
    Simulation sim(sc);
    int calls = 0;
    struct Stop {};
    sim.add_observer(std::make_shared<CheckpointObserver>([&] { return ++calls == 5; },
                                                          [&](const Checkpoint& c) {
                                                            write_checkpoint(path, c);
                                                            throw Stop{};
                                                          }));
    EXPECT_THROW(sim.run(), Stop);
  }
  const Checkpoint c = read_checkpoint(path);
  std::filesystem::remove(path);
  EXPECT_EQ(c.reduced, "omega2");
  EXPECT_EQ(c.integrator.y.size(), 6u * 32u + 7u);  // six rows + the s = 0 anchor

  Simulation sim(sc);
  sim.resume_from(c);
  rodtest::RunResult rest;
  sim.add_observer(on_frame([&](const Frame& f) { rest.y.emplace_back(f.y, f.y + 12 * f.N); }));
  rest.summary = sim.run();
  EXPECT_TRUE(rest.summary.reduced);
  ASSERT_EQ(rest.y.size(), whole.y.size() - static_cast<std::size_t>(c.next_frame));
  for (std::size_t j = 0; j < rest.y.size(); ++j)
    EXPECT_EQ(rest.y[j], whole.y[j + static_cast<std::size_t>(c.next_frame)]) << "frame " << j;

  // A reduced checkpoint cannot be resumed by a scene that forbids it.
  Scene twisted = sc;
  twisted.initial.kind = InitialKind::rest;
  twisted.initial.numbers.clear();
  twisted.rod.Omega0 = {0.0, 0.0, 0.5};
  Simulation other(twisted);
  EXPECT_THROW(other.resume_from(c), InputError);
}

}  // namespace
