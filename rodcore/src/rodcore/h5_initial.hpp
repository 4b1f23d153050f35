// Initial and intrinsic fields from HDF5 files, so any state made elsewhere
// (Python, another run) can be run (scene `initial.kind = "file"`,
// `rod.intrinsic_file`). Layout of the files (docs/scenes.md):
//   s               (N)      grid s_i = i L / N; must match the scene's grid
//   fields/gamma    (N x 3)  internal frame, dimensionless
//   fields/omega    (N x 3)
//   fields/Gamma    (N x 3)
//   fields/Omega    (N x 3)
// and for the intrinsic shape: datasets Gamma0, Omega0 (N x 3); and the
// per-point material file (attribute format = "dnarod-material/1"):
//   K (N x 6 x 6), I (N x 3 x 3), rho (N) [, Gamma0, Omega0 (N x 3)].
// Every problem is an InputError naming the file, the dataset and, for bad
// numbers, the index.
#pragma once
#include <string>
#include <vector>

#include "rodcore/scene.hpp"

namespace rodcore {

// Reads the four fields at the grid points `s` into `y` (resized to 12 N,
// layout of state.hpp).
void read_initial_fields(const std::string& path, const std::vector<double>& s, std::vector<double>& y);

// Reads datasets Gamma0 and Omega0 (N x 3) into component-major arrays of
// 3 N values ([c * N + i]), the layout of Rod::Gamma0_s / Rod::Omega0_s.
void read_intrinsic_shape(const std::string& path, int N, std::vector<double>& Gamma0_s,
                          std::vector<double>& Omega0_s);

inline constexpr const char* kMaterialFormat = "dnarod-material/1";

// Reads a material file for N = rod.points into m.K_s, m.I_s, m.rho_s (layout
// of Material) and m.file, validating every point (material.hpp); its
// optional intrinsic shape into Gamma0_s, Omega0_s (component-major, left
// empty when the file has none).
void read_material_file(const std::string& path, int N, Material& m, std::vector<double>& Gamma0_s,
                        std::vector<double>& Omega0_s);

// Writes `s` and the four fields of `y` (12 N, state layout) in the format
// read_initial_fields reads. Used by the Python module (initial= arrays) and
// by tests; throws Error if the file cannot be written.
void write_initial_fields(const std::string& path, const std::vector<double>& s,
                          const std::vector<double>& y);

}  // namespace rodcore
