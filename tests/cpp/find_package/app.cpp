// Runs a scene through rodcore's public headers only, as an outside project
// would, and checks physics the solver does not know it is tested on:
//   app SCENE.toml OUT.h5
// SCENE is the exact twisted-rod wave (paper Eq 24, workflows/scenes/twisted_wave.toml):
// Gamma1(s, t) = A cos(w t - k s) with w from the dispersion relation Eq 26,
// written out here independently of rodcore. Checks, at the half period and
// at the end: |Gamma1 - exact| <= 1e-7, the energy (Appendix A) conserved to
// 1e-9, and that an observer saw every output frame. Prints "ok" or the failure.
#include <cmath>
#include <cstdio>
#include <memory>
#include <numbers>
#include <string>

#include "rodcore/error.hpp"
#include "rodcore/h5_writer.hpp"
#include "rodcore/observer.hpp"
#include "rodcore/scene_io.hpp"
#include "rodcore/simulation.hpp"
#include "rodcore/version.hpp"

namespace {

struct CountFrames : rodcore::Observer {
  int frames = 0;
  void frame(const rodcore::Simulation&, const rodcore::Frame&) override { ++frames; }
};

// Eq 26: the w_+ branch of the bend-shear wave of a twisted rod.
double w_plus(double kappa, double D1, double Gamma03) {
  const double sD = std::sqrt(D1);
  const double a = std::sqrt(kappa * kappa * (sD + 1) * (sD + 1) + Gamma03 * Gamma03);
  const double b = std::sqrt(kappa * kappa * (sD - 1) * (sD - 1) + Gamma03 * Gamma03);
  return 0.5 * (a + b);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: app SCENE.toml OUT.h5\n");
    return 2;
  }
  try {
    const rodcore::Scene scene = rodcore::read_scene_file(argv[1]);
    rodcore::Simulation sim(scene);
    auto count = std::make_shared<CountFrames>();
    sim.add_observer(count);
    sim.add_observer(std::make_shared<rodcore::H5Writer>(argv[2], sim));

    const double A = scene.initial.numbers.at("A");
    const double L = scene.rod.length;
    const double k = 2 * std::numbers::pi * scene.initial.numbers.at("mode") / L;
    const double kappa = k + scene.rod.Omega0[2];  // kappa = "p" branch
    const double w = w_plus(kappa, scene.material.D[0], scene.rod.Gamma0[2]);
    const auto s = sim.grid();
    const std::size_t N = s.size();
    const double E0 = sim.energy();

    auto check = [&](double t) {
      double err = 0;
      const double* Gamma1 = sim.state().data() + 6 * N;  // row Gamma1 (state.hpp)
      for (std::size_t i = 0; i < N; ++i)
        err = std::fmax(err, std::abs(Gamma1[i] - A * std::cos(w * t - k * s[i])));
      const double drift = std::abs(sim.energy() - E0) / std::abs(E0);
      std::printf("t = %.6f: max |Gamma1 - exact| = %.3e, energy drift = %.3e\n", t, err, drift);
      return err <= 1e-7 && drift <= 1e-9;
    };
    const double half_period = std::numbers::pi / w;
    sim.step_to(half_period);
    bool ok = check(half_period);
    const rodcore::RunSummary summary = sim.run();
    ok = check(sim.time()) && ok;
    if (count->frames != scene.output.frames) {
      std::printf("the observer saw %d frames, the scene has %d\n", count->frames, scene.output.frames);
      ok = false;
    }
    std::printf("rodcore %s: %ld steps, method %s\n%s\n", rodcore::kRodcoreVersion, summary.steps,
                summary.method.c_str(), ok ? "ok" : "FAILED");
    return ok ? 0 : 1;
  } catch (const rodcore::Error& e) {
    std::fprintf(stderr, "app: %s\n", e.what());
    return 2;
  }
}
