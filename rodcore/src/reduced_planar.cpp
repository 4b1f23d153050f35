#include "rodcore/reduced_planar.hpp"

#include <algorithm>

namespace rodcore {

bool planar_reduction_allowed(const Rod& rod) {
  return rod.Gamma0_s.empty() && rod.Omega0_s.empty() && rod.Gamma0[0] == 0.0 &&
         rod.Gamma0[1] == 0.0 && rod.Omega0[0] == 0.0 && rod.Omega0[1] == 0.0 &&
         rod.Omega0[2] == 0.0;
}

bool in_planar_subspace(const double* y, std::size_t N) {
  for (int r : kPlanarZeroRows)
    for (std::size_t i = 0; i < N; ++i)
      if (y[r * N + i] != 0.0) return false;
  return true;
}

PlanarRHS::PlanarRHS(RodRHS& full) : full_(full), N_(full.N()), y_(12 * N_, 0.0), f_(12 * N_, 0.0) {
  std::vector<int> rows(kPlanarRows.begin(), kPlanarRows.end());
  full_.set_nonzero_rows(rows);
}

PlanarRHS::~PlanarRHS() { full_.set_nonzero_rows({}); }

void PlanarRHS::expand(const double* y6, double* y12) const {
  std::fill(y12, y12 + 12 * N_, 0.0);
  for (std::size_t k = 0; k < kPlanarRows.size(); ++k)
    std::copy(y6 + k * N_, y6 + (k + 1) * N_, y12 + kPlanarRows[k] * N_);
}

void PlanarRHS::reduce(const double* y12, double* y6) const {
  for (std::size_t k = 0; k < kPlanarRows.size(); ++k)
    std::copy(y12 + kPlanarRows[k] * N_, y12 + (kPlanarRows[k] + 1) * N_, y6 + k * N_);
}

void PlanarRHS::operator()(const double* y6, double* f6) const {
  // The zero rows of y_ are never written, so only the kept rows are copied.
  for (std::size_t k = 0; k < kPlanarRows.size(); ++k)
    std::copy(y6 + k * N_, y6 + (k + 1) * N_, y_.data() + kPlanarRows[k] * N_);
  full_(y_.data(), f_.data());
  reduce(f_.data(), f6);
}

}  // namespace rodcore
