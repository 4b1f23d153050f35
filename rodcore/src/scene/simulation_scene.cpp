// The parts of Simulation that belong to the scene layer: making the initial
// state from a scene's initial condition (a kind, possibly in DNA units,
// initial_conditions.hpp) and recording the scene in checkpoints. The solver
// core (simulation.cpp) only ever sees the dimensionless InitialState.
#include <set>

#include "rodcore/checkpoint.hpp"
#include "rodcore/guards.hpp"
#include "rodcore/initial_conditions.hpp"
#include "rodcore/simulation.hpp"

namespace rodcore {
namespace {

// A scene built in code may leave the rod to the kind (e.g. dna_planar).
Scene with_rod(const Scene& scene) {
  Scene sc = scene;
  const InitialKindSpec& kind = initial_kind_spec(sc.initial.kind);
  if (kind.derive_rod && (sc.rod.length <= 0.0 || sc.rod.points <= 0)) {
    std::set<std::string> keys;
    if (sc.rod.points > 0) keys.insert("points");
    kind.derive_rod(sc.initial, sc.rod, sc.material, keys);
  }
  validate_run_settings(sc);
  return sc;
}

InitialState initial_state_of(const Scene& sc) {
  InitialState init;
  init.y = make_initial_state(sc);
  if (sc.output.centerline || sc.output.directors) {
    const auto [q0, r0] = initial_anchor(sc);
    init.q0 = q0;
    init.r0 = r0;
  }
  return init;
}

}  // namespace

Simulation::Simulation(const Scene& scene) : Simulation(with_rod(scene), initial_state_of(with_rod(scene))) {}

Checkpoint Simulation::checkpoint() const {
  Checkpoint c = run_point();
  c.scene = checkpoint_scene_text(given_scene());
  return c;
}

}  // namespace rodcore
