// The run loop as observers (rodcore/include/rodcore/observer.hpp, docs/architecture.md):
// the order of the calls, that the scene's checks run before any observer of
// the user (a frame that fails a check is never delivered), that a failure
// reaches failed() and not finished(), and that step_to() in pieces gives the
// frames of one run bit for bit (steps are never shortened to stop at t).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "physics_test_util.hpp"
#include "rodcore/error.hpp"
#include "rodcore/observer.hpp"
#include "rodcore/simulation.hpp"

using namespace rodcore;

namespace {

struct Recorder : Observer {
  std::vector<std::string> calls;
  std::vector<double> frame_t;
  std::vector<std::vector<double>> frame_y;
  long steps = 0;
  std::string failure;
  void started(const Simulation&) override { calls.push_back("started"); }
  void step(const Simulation&, const StepView& v) override {
    ++steps;
    calls.push_back("step");
    EXPECT_EQ(v.n, v.rows->size() * v.N);  // no reconstruction in these scenes
  }
  void frame(const Simulation&, const Frame& f) override {
    calls.push_back("frame");
    frame_t.push_back(f.t);
    frame_y.emplace_back(f.y, f.y + 12 * f.N);
  }
  void stepped(const Simulation& sim) override {
    calls.push_back("stepped");
    // Every frame up to the integrator's time is out: a checkpoint now is complete.
    const int j = sim.frames_delivered();
    if (j < sim.scene().output.frames) {
      EXPECT_GT(sim.frame_time(j), sim.integrator_time());
    }
  }
  void finished(const Simulation&, const RunSummary&) override { calls.push_back("finished"); }
  void failed(const Simulation&, const std::string& m) override {
    calls.push_back("failed");
    failure = m;
  }
};

Scene wave(double t_end = 1.0, int frames = 6) {
  Scene sc = rodtest::twisted_wave_scene(32, "p", "plus", 0.3);
  sc.solver.space = SpaceMethod::spectral;
  sc.solver.time = TimeMethod::dop853;
  sc.output.t_end = t_end;
  sc.output.frames = frames;
  sc.output.energy = true;
  return sc;
}

}  // namespace

TEST(ApiObservers, CallOrderOfARun) {
  Simulation sim(wave());
  auto rec = std::make_shared<Recorder>();
  sim.add_observer(rec);
  const RunSummary sum = sim.run();
  ASSERT_GE(rec->calls.size(), 3u);
  EXPECT_EQ(rec->calls.front(), "started");
  EXPECT_EQ(rec->calls[1], "frame");  // frame 0 before any step
  EXPECT_EQ(rec->calls.back(), "finished");
  EXPECT_EQ(rec->steps, sum.steps);
  EXPECT_EQ(rec->frame_t.size(), 6u);
  for (std::size_t k = 0; k < rec->frame_t.size(); ++k)
    EXPECT_EQ(rec->frame_t[k], sim.frame_time(static_cast<int>(k)));
  // Between two steps: frames come after their step and before its "stepped".
  for (std::size_t i = 2; i + 1 < rec->calls.size(); ++i)
    if (rec->calls[i] == "frame") {
      EXPECT_TRUE(rec->calls[i - 1] == "step" || rec->calls[i - 1] == "frame") << i;
    }
}

TEST(ApiObservers, StepToInPiecesEqualsOneRun) {
  Recorder whole;
  {
    Simulation sim(wave());
    auto rec = std::make_shared<Recorder>();
    sim.add_observer(rec);
    sim.run();
    whole = *rec;
  }
  Simulation sim(wave());
  auto rec = std::make_shared<Recorder>();
  sim.add_observer(rec);
  for (double t : {0.05, 0.333, 0.5, 0.51, 1.0}) {
    sim.step_to(t);
    EXPECT_EQ(sim.time(), t);
  }
  EXPECT_EQ(rec->steps, whole.steps);
  ASSERT_EQ(rec->frame_y.size(), whole.frame_y.size());
  for (std::size_t k = 0; k < whole.frame_y.size(); ++k)
    EXPECT_TRUE(rec->frame_y[k] == whole.frame_y[k]) << k;
  EXPECT_TRUE(sim.state() == whole.frame_y.back());
  EXPECT_THROW(sim.step_to(0.5), InputError);  // backwards
}

TEST(ApiObservers, AFailedCheckStopsBeforeTheFrameReachesTheUser) {
  Scene sc = wave();
  sc.checks.max_energy_drift = 1e-300;  // every frame after t = 0 drifts more than this
  Simulation sim(sc);
  auto rec = std::make_shared<Recorder>();
  sim.add_observer(rec);
  EXPECT_THROW(sim.run(), NumericalError);
  EXPECT_EQ(rec->frame_t.size(), 1u);  // frame 0 only
  EXPECT_EQ(rec->calls.back(), "failed");
  EXPECT_NE(rec->failure.find("checks.max_energy_drift"), std::string::npos) << rec->failure;
  // Control: the same scene without the bound delivers every frame.
  Simulation ok(wave());
  auto rec2 = std::make_shared<Recorder>();
  ok.add_observer(rec2);
  ok.run();
  EXPECT_EQ(rec2->frame_t.size(), 6u);
}

TEST(ApiObservers, FoldingIsCaughtAfterTheStep) {
  Scene sc = wave();
  sc.initial.kind = InitialKind::rest;
  sc.initial.numbers.clear();
  sc.initial.strings.clear();
  const std::size_t N = 32;
  InitialState init;
  init.y.assign(12 * N, 0.0);
  for (std::size_t i = 0; i < N; ++i) {
    const double s = static_cast<double>(i) * sc.rod.length / N;  // L = pi: mode 1 is sin 2s
    init.y[8 * N + i] = 1.0 - 0.9999 * std::cos(2 * s);           // Gamma3 = 1e-4 at s = 0 ...
    init.y[2 * N + i] = -5.0 * std::sin(2 * s);                   // ... compressed there: d gamma3/ds = -10
    init.y[11 * N + i] = 1.0;                                     // Omega3 = Omega03
  }
  Simulation sim(sc, init);
  auto rec = std::make_shared<Recorder>();
  sim.add_observer(rec);
  EXPECT_THROW(sim.run(), NumericalError);
  EXPECT_NE(rec->failure.find("folded"), std::string::npos) << rec->failure;
  EXPECT_EQ(rec->calls.back(), "failed");
  EXPECT_EQ(std::count(rec->calls.begin(), rec->calls.end(), "finished"), 0);
}

TEST(ApiObservers, GivenInitialStateOfTheWrongSizeIsAnInputError) {
  InitialState init;
  init.y.assign(5, 0.0);
  EXPECT_THROW(Simulation(wave(), init), InputError);
}
