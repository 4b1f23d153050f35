// The scene's [checks] as observers of the run loop (observer.hpp): bad
// numbers never pass silently. Each throws NumericalError with a message
// that says what, where and what to try; the frames delivered before stay.
//   non-finite   NaN/Inf anywhere in the integrated state, after every step
//   fold         Gamma3 <= 0 somewhere (checks.stop_on_fold), after every step
//   energy       non-finite energy, or relative drift > checks.max_energy_drift,
//                at the frames where the energy is computed
//   directors    director norm error > checks.max_director_norm_error, at
//                frames with a reconstruction
// Simulation adds them first, so a frame that fails a check is never handed
// to the output observers.
#pragma once
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "rodcore/observer.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

std::vector<std::unique_ptr<Observer>> make_guards(const Scene& scene, const std::vector<double>& s);

// The run settings a Simulation needs before anything else (rod size,
// output times, enum values that are one of their table's). Throws InputError.
void validate_run_settings(const Scene& scene);

// The thermal settings that span sections (docs/thermal.md): the dotted key
// and what is wrong with it, or two empty strings. The scene reader reports it
// at the key's line; validate_run_settings() for a scene built in code.
std::pair<std::string, std::string> thermal_settings_problem(const Scene& scene);

// Throws InputError naming the first non-finite initial value (component, point, s).
void check_initial_finite(const Scene& scene, const std::vector<double>& y, const std::vector<double>& s);

}  // namespace rodcore
