#include "rodcore/reduced_planar.hpp"

#include <algorithm>

namespace rodcore {

bool planar_reduction_allowed(const Rod& rod) {
  return rod.Gamma0_s.empty() && rod.Omega0_s.empty() && rod.Gamma0[0] == 0.0 && rod.Gamma0[1] == 0.0 &&
         rod.Omega0[0] == 0.0 && rod.Omega0[1] == 0.0 && rod.Omega0[2] == 0.0;
}

std::string planar_material_coupling(const MaterialField& mf, Planar p) {
  // Strain indices (Gamma1..3, Omega1..3 = 0..5) kept, and the omega axis.
  return p == Planar::omega2 ? planar_coupling(mf, {0, 2, 4}, 1) : planar_coupling(mf, {1, 2, 3}, 0);
}

const char* planar_name(Planar p) { return p == Planar::omega2 ? "omega2" : "omega1"; }

std::optional<Planar> planar_from_name(const std::string& name) {
  if (name == "omega2") return Planar::omega2;
  if (name == "omega1") return Planar::omega1;
  return std::nullopt;
}

const std::array<int, 6>& planar_rows(Planar p) { return p == Planar::omega2 ? kPlanarRows : kPlanarRows1; }
const std::array<int, 6>& planar_zero_rows(Planar p) {
  return p == Planar::omega2 ? kPlanarZeroRows : kPlanarZeroRows1;
}

bool in_planar_subspace(const double* y, std::size_t N, Planar p) {
  for (int r : planar_zero_rows(p))
    for (std::size_t i = 0; i < N; ++i)
      if (y[r * N + i] != 0.0) return false;
  return true;
}

std::optional<Planar> planar_polarisation(const double* y, std::size_t N) {
  if (in_planar_subspace(y, N, Planar::omega2)) return Planar::omega2;
  if (in_planar_subspace(y, N, Planar::omega1)) return Planar::omega1;
  return std::nullopt;
}

PlanarRHS::PlanarRHS(RodRHS& full, Planar p) : full_(full), N_(full.N()), rows_(planar_rows(p)) {
  std::vector<int> rows(rows_.begin(), rows_.end());
  full_.set_nonzero_rows(rows);
}

PlanarRHS::~PlanarRHS() { full_.set_nonzero_rows({}); }

void PlanarRHS::expand(const double* y6, double* y12) const {
  std::fill(y12, y12 + 12 * N_, 0.0);
  for (std::size_t k = 0; k < rows_.size(); ++k)
    std::copy(y6 + k * N_, y6 + (k + 1) * N_, y12 + rows_[k] * N_);
}

void PlanarRHS::reduce(const double* y12, double* y6) const {
  for (std::size_t k = 0; k < rows_.size(); ++k)
    std::copy(y12 + rows_[k] * N_, y12 + (rows_[k] + 1) * N_, y6 + k * N_);
}

void PlanarRHS::operator()(const double* y6, double* f6) const {
  full_.reduced(rows_ == kPlanarRows ? 1 : 2, rows_, y6, f6);
}

}  // namespace rodcore
