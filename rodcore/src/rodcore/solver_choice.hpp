// How a scene is solved, each choice with its reason for the run's notes:
// solver.space and solver.time resolved from "automatic" (docs/performance.md,
// "Default method rule"), and whether the run integrates only a planar
// polarisation (solver.reduce; reduced_planar.hpp, paper Sec 4.1).
#pragma once
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rodcore/material.hpp"
#include "rodcore/reduced_planar.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

// solver.space / solver.time = automatic -> the measured default, from the
// scene and its initial 12 N state y0; `note` says what and why.
void resolve_method(Scene& scene, const std::vector<double>& y0, std::string& note);

// The polarisation the 12 N initial state y lies in, exactly, when the scene
// allows the reduction (solver.reduce, no [thermal] or [contact], a uniform
// intrinsic shape and material that keep the polarisation), else none;
// `note` says which and why (not).
std::optional<Planar> choose_reduction(const Scene& scene, const MaterialField& mf, const double* y,
                                       std::size_t N, std::string& note);

// The rod and material of `scene` keep polarisation p invariant (a checkpoint
// of the reduced system may be resumed).
bool reduction_allowed(const Scene& scene, const MaterialField& mf, Planar p);

}  // namespace rodcore
