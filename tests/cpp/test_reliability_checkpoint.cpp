// Checkpoints (docs/reliability.md, "Checkpoints and resume"): a run stopped at any step
// boundary and continued from its checkpoint FILE gives the same bits as a
// run that never stopped -- for every time integrator, fixed-step and
// adaptive (step size and PI-controller memory are restored), with the
// reconstruction anchor (centerline, directors) and the energy-drift check.
// The independent truth is the uninterrupted run of the same scene.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "physics_test_util.hpp"
#include "rodcore/checkpoint.hpp"
#include "rodcore/error.hpp"
#include "rodcore/simulation.hpp"
#include "signals.hpp"  // rodsim's stop signals and schedule (rodcore/cli)
#include "temp_dir.hpp"

namespace fs = std::filesystem;
using namespace rodcore;

namespace {

struct Stop {};  // thrown by the test's save hook to end the first half

// A small valid checkpoint (not of any scene), for the file-level tests.
Checkpoint small_checkpoint(TimeMethod method) {
  Checkpoint c;
  c.scene = "s";
  c.method = method;
  c.integrator.dt_next = 0.1;
  c.integrator.y = c.integrator.f = {1.0, 2.0};
  c.next_frame = 1;
  c.E0 = 1.0;
  return c;
}

Scene scene_for(const std::string& time) {
  Scene sc = rodtest::twisted_wave_scene(24, "p", "plus", 0.5);
  sc.solver.time = *from_string<TimeMethod>(time);
  sc.solver.rtol = sc.solver.atol = 1e-11;
  sc.solver.dt = time == "rk4" || time == "langevin" ? 0.01 : 0.05;  // brownian: 52 steps
  sc.output.t_end = 2.6;
  sc.output.frames = 14;
  sc.output.energy = true;
  sc.output.centerline = true;
  sc.output.directors = true;
  sc.checks.max_energy_drift = 1e-3;
  if (time == "langevin") {  // the thermal rod: its random numbers resume with the step index
    sc.thermal.on = true;
    sc.thermal.kT = 1e-3;
    sc.thermal.friction_translational = {0.5, 1.0};
    sc.thermal.friction_rotational = {2.0, 1.0};
    sc.checks.max_energy_drift = std::numeric_limits<double>::infinity();  // a bath exchanges energy
  }
  if (time == "brownian") {  // the overdamped rod: noise by step index, the closure's Newton steps
    sc.solver.space = SpaceMethod::fd4;
    sc.thermal.on = true;
    sc.thermal.kT = 1e-3;
    sc.thermal.friction_translational = {0.5, 1.0};
    sc.thermal.friction_rotational = {2.0, 1.0};
    sc.thermal.closure_interval = 0.0;  // projected every step, as the kilobase ring is
    sc.checks.max_energy_drift = std::numeric_limits<double>::infinity();
  }
  return sc;
}

struct Frames {
  std::vector<double> t, energy;
  std::vector<std::vector<double>> y, centerline, directors;
  void add(const Frame& f) {
    t.push_back(f.t);
    energy.push_back(f.energy.value_or(-1.0));
    y.emplace_back(f.y, f.y + 12 * f.N);
    centerline.emplace_back(f.centerline, f.centerline + 3 * f.N);
    directors.emplace_back(f.directors, f.directors + 9 * f.N);
  }
};

class CheckpointResume : public ::testing::TestWithParam<std::string> {};

TEST_P(CheckpointResume, ResumedRunIsBitwiseTheUninterruptedRun) {
  TempDir dir;
  const std::string file = (dir.path / "run.h5.ckpt").string();
  const Scene sc = scene_for(GetParam());

  Frames whole;
  Simulation ref(sc);
  ref.add_observer(on_frame([&](const Frame& f) { whole.add(f); }));
  const RunSummary ref_sum = ref.run();
  ASSERT_EQ(whole.t.size(), 14u);
  ASSERT_GT(ref_sum.steps, 20) << "too few steps to stop in the middle";

  // Stop at several different step boundaries (early, middle, late).
  for (long stop_at : {1L, ref_sum.steps / 2, ref_sum.steps - 2}) {
    SCOPED_TRACE("stopped after step " + std::to_string(stop_at));
    Frames parts;
    {
      Simulation first(sc);
      long calls = 0;
      first.add_observer(std::make_shared<CheckpointObserver>([&] { return ++calls == stop_at; },
                                                              [&](const Checkpoint& c) {
                                                                write_checkpoint(file, c);
                                                                throw Stop{};
                                                              }));
      first.add_observer(on_frame([&](const Frame& f) { parts.add(f); }));
      EXPECT_THROW(first.run(), Stop);
    }
    const Checkpoint c = read_checkpoint(file);
    EXPECT_EQ(c.next_frame, static_cast<int>(parts.t.size()));
    EXPECT_EQ(to_string(c.method), GetParam());
    EXPECT_NO_THROW(check_checkpoint_matches(c, sc, file));
    Simulation second(sc);
    second.resume_from(c);
    second.add_observer(on_frame([&](const Frame& f) { parts.add(f); }));
    const RunSummary sum = second.run();

    ASSERT_EQ(parts.t.size(), whole.t.size());
    for (std::size_t k = 0; k < whole.t.size(); ++k) {
      EXPECT_EQ(parts.t[k], whole.t[k]) << "frame " << k;
      EXPECT_EQ(parts.energy[k], whole.energy[k]) << "frame " << k;
      EXPECT_TRUE(parts.y[k] == whole.y[k]) << "state differs at frame " << k;
      EXPECT_TRUE(parts.centerline[k] == whole.centerline[k]) << "centerline differs at frame " << k;
      EXPECT_TRUE(parts.directors[k] == whole.directors[k]) << "directors differ at frame " << k;
    }
    EXPECT_EQ(sum.steps, ref_sum.steps);
    EXPECT_EQ(sum.rejected, ref_sum.rejected);
    EXPECT_EQ(sum.rhs_evaluations, ref_sum.rhs_evaluations);
    EXPECT_EQ(sum.energy_drift, ref_sum.energy_drift);
  }
}

INSTANTIATE_TEST_SUITE_P(EveryIntegrator, CheckpointResume,
                         ::testing::Values("rk4", "rk4-doubling", "dopri5", "dop853", "langevin", "brownian"),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (auto& ch : n)
                             if (ch == '-') ch = '_';
                           return n;
                         });

TEST(ReliabilityCheckpoint, ResumedBrownianRunWithAnotherSeedDiffers) {
  // control for the brownian case above: the comparison sees the random numbers after the
  // checkpoint (a resumed run whose seed differs leaves the uninterrupted run's states)
  TempDir dir;
  const std::string file = (dir.path / "run.h5.ckpt").string();
  const Scene sc = scene_for("brownian");
  Frames whole;
  Simulation ref(sc);
  ref.add_observer(on_frame([&](const Frame& f) { whole.add(f); }));
  const RunSummary ref_sum = ref.run();
  Frames parts;
  {
    Simulation first(sc);
    long calls = 0;
    first.add_observer(std::make_shared<CheckpointObserver>([&] { return ++calls == ref_sum.steps / 2; },
                                                            [&](const Checkpoint& c) {
                                                              write_checkpoint(file, c);
                                                              throw Stop{};
                                                            }));
    first.add_observer(on_frame([&](const Frame& f) { parts.add(f); }));
    EXPECT_THROW(first.run(), Stop);
  }
  const std::size_t before = parts.t.size();
  Scene other = sc;
  other.thermal.seed = sc.thermal.seed + 1;
  Simulation second(other);
  second.resume_from(read_checkpoint(file));
  second.add_observer(on_frame([&](const Frame& f) { parts.add(f); }));
  second.run();
  ASSERT_EQ(parts.t.size(), whole.t.size());
  for (std::size_t k = 0; k < before; ++k) EXPECT_TRUE(parts.y[k] == whole.y[k]) << "frame " << k;
  for (std::size_t k = before; k < whole.t.size(); ++k)
    EXPECT_FALSE(parts.y[k] == whole.y[k]) << "frame " << k << " after the resume";
}

TEST(ReliabilityCheckpoint, FileRoundTripIsExact) {
  TempDir dir;
  const std::string file = (dir.path / "x.ckpt").string();
  Checkpoint c;
  c.scene = "[rod]\nlength = 1\n";
  c.method = TimeMethod::dopri5;
  c.integrator.t = 0.1 + 0.2;  // not a short decimal: must survive bit for bit
  c.integrator.dt_next = 1.0 / 3.0;
  c.integrator.y = {1e-300, -0.0, 3.141592653589793, 2.0 / 7.0};
  c.integrator.f = {4.9e-324, 1.0, -1.0, 1e300};
  c.integrator.controller = {0.123456789012345678};
  c.integrator.steps = 123456789012LL;
  c.integrator.rejected = 7;
  c.integrator.rhs_evaluations = 99;
  c.next_frame = 5;
  c.E0 = 1.0 / 7.0;
  c.energy_drift = 1e-13;
  c.wall_seconds = 12.5;
  write_checkpoint(file, c);
  EXPECT_FALSE(fs::exists(file + ".tmp")) << "the temporary file must be renamed away";
  const Checkpoint d = read_checkpoint(file);
  EXPECT_EQ(d.scene, c.scene);
  EXPECT_EQ(d.method, c.method);
  EXPECT_EQ(d.integrator.t, c.integrator.t);
  EXPECT_EQ(d.integrator.dt_next, c.integrator.dt_next);
  EXPECT_EQ(d.integrator.y, c.integrator.y);
  EXPECT_EQ(d.integrator.f, c.integrator.f);
  EXPECT_EQ(d.integrator.controller, c.integrator.controller);
  EXPECT_EQ(d.integrator.steps, c.integrator.steps);
  EXPECT_EQ(d.integrator.rejected, c.integrator.rejected);
  EXPECT_EQ(d.integrator.rhs_evaluations, c.integrator.rhs_evaluations);
  EXPECT_EQ(d.next_frame, c.next_frame);
  EXPECT_EQ(d.E0, c.E0);
  EXPECT_EQ(d.energy_drift, c.energy_drift);
  EXPECT_EQ(d.wall_seconds, c.wall_seconds);
  EXPECT_TRUE(std::signbit(d.integrator.y[1]));
}

TEST(ReliabilityCheckpoint, InterruptedWriteKeepsThePreviousCheckpoint) {
  // A kill during a write leaves at most a damaged OUT.h5.ckpt.tmp; the
  // published checkpoint is the previous one and still reads.
  TempDir dir;
  const std::string file = (dir.path / "x.ckpt").string();
  Checkpoint c = small_checkpoint(TimeMethod::rk4);
  write_checkpoint(file, c);
  { std::ofstream(file + ".tmp") << "half a checkpoint"; }
  EXPECT_EQ(read_checkpoint(file).integrator.y, c.integrator.y);
  c.integrator.y = {3.0, 4.0};
  write_checkpoint(file, c);  // a later write replaces the stale temp file
  EXPECT_EQ(read_checkpoint(file).integrator.y, c.integrator.y);
}

TEST(ReliabilityCheckpoint, DamagedOrMissingCheckpointNamesTheFile) {
  TempDir dir;
  const std::string missing = (dir.path / "none.ckpt").string();
  try {
    read_checkpoint(missing);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none.ckpt' does not exist"), std::string::npos) << e.what();
  }
  const std::string junk = (dir.path / "junk.ckpt").string();
  { std::ofstream(junk) << "not hdf5"; }
  try {
    read_checkpoint(junk);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("junk.ckpt' is not an HDF5 file"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("without --resume"), std::string::npos) << e.what();
  }
  // A method that is no time integrator (the file holds solver.time's spelling).
  const std::string odd = (dir.path / "odd.ckpt").string();
  Checkpoint c = small_checkpoint(TimeMethod::dopri5);
  write_checkpoint(odd, c);
  EXPECT_EQ(read_checkpoint(odd).method, TimeMethod::dopri5);  // control: the file as written reads
  for (const char* method : {"euler", "auto"}) {
    hid_t f = H5Fopen(odd.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
    ASSERT_GE(f, 0);
    H5Adelete(f, "method");
    hid_t t = H5Tcopy(H5T_C_S1), sp = H5Screate(H5S_SCALAR);
    H5Tset_size(t, H5T_VARIABLE);
    hid_t a = H5Acreate2(f, "method", t, sp, H5P_DEFAULT, H5P_DEFAULT);
    H5Awrite(a, t, &method);
    H5Aclose(a), H5Sclose(sp), H5Tclose(t), H5Fclose(f);
    try {
      read_checkpoint(odd);
      ADD_FAILURE() << method;
    } catch (const InputError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("attribute 'method' = \"" + std::string(method) + "\" is not a time integrator"),
                std::string::npos)
          << m;
    }
  }
}

TEST(ReliabilityCheckpoint, CheckpointOfAnotherSceneIsRefused) {
  TempDir dir;
  const std::string file = (dir.path / "x.ckpt").string();
  Scene a = scene_for("dop853");
  Scene b = a;
  b.solver.rtol = 1e-9;
  Checkpoint c;
  c.scene = checkpoint_scene_text(a);
  c.method = TimeMethod::dop853;
  try {
    check_checkpoint_matches(c, b, file);
    FAIL();
  } catch (const InputError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("x.ckpt' was written by a run of a different scene"), std::string::npos) << m;
    EXPECT_NE(m.find("rtol"), std::string::npos) << m;
  }
  // The checkpoint interval may differ between a run and its resume.
  Scene d = a;
  d.output.checkpoint_interval_s = 30.0;
  EXPECT_NO_THROW(check_checkpoint_matches(c, d, file));
  // A checkpoint of another integrator or size is refused by the simulation.
  Simulation sim(b);
  c.method = TimeMethod::rk4;
  EXPECT_THROW(sim.resume_from(c), InputError);
}

TEST(ReliabilityCheckpoint, StopSignalSetsTheFlagAndMakesACheckpointDue) {
  clear_stop_signal();
  CheckpointSchedule never(0.0), later(3600.0), always(1e-6);
  std::this_thread::sleep_for(std::chrono::milliseconds(2));
  EXPECT_FALSE(never.due());
  EXPECT_FALSE(later.due());
  EXPECT_TRUE(always.due());
  install_stop_signal_handlers();
  std::raise(SIGTERM);  // handled: the process goes on
  EXPECT_EQ(stop_signal(), SIGTERM);
  EXPECT_TRUE(never.due());
  EXPECT_TRUE(later.due());
  clear_stop_signal();
  std::signal(SIGTERM, SIG_DFL);
  std::signal(SIGINT, SIG_DFL);
}

}  // namespace
