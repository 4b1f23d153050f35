// Initial and intrinsic fields from HDF5 files, so any state made elsewhere
// (Python, another run) can be run (scene `initial.kind = "file"`,
// `rod.intrinsic_file`). Layout of the files (docs/scenes.md):
//   s               (N)      grid s_i = i L / N; must match the scene's grid
//   fields/gamma    (N x 3)  internal frame, dimensionless
//   fields/omega    (N x 3)
//   fields/Gamma    (N x 3)
//   fields/Omega    (N x 3)
// and for the intrinsic shape: datasets Gamma0, Omega0 (N x 3).
// Every problem is an InputError naming the file, the dataset and, for bad
// numbers, the index.
#pragma once
#include <string>
#include <vector>

namespace rodcore {

// Reads the four fields at the grid points `s` into `y` (resized to 12 N,
// layout of state.hpp).
void read_initial_fields(const std::string& path, const std::vector<double>& s,
                         std::vector<double>& y);

// Reads datasets Gamma0 and Omega0 (N x 3) into component-major arrays of
// 3 N values ([c * N + i]), the layout of Rod::Gamma0_s / Rod::Omega0_s.
void read_intrinsic_shape(const std::string& path, int N, std::vector<double>& Gamma0_s,
                          std::vector<double>& Omega0_s);

// Writes `s` and the four fields of `y` (12 N, state layout) in the format
// read_initial_fields reads. Used by the Python module (initial= arrays) and
// by tests; throws Error if the file cannot be written.
void write_initial_fields(const std::string& path, const std::vector<double>& s,
                          const std::vector<double>& y);

}  // namespace rodcore
