// Diagnostics of a rod state (paper Appendix A). The energy
//   E = 1/2 int_0^L { |gamma|^2 + omega.I omega + (Gamma-Gamma0).C(Gamma-Gamma0)
//                     + (Omega-Omega0).D(Omega-Omega0) } ds
// is evaluated with the periodic trapezoid rule h sum_i (spectrally accurate
// for smooth periodic integrands). It is conserved exactly by the
// semi-discrete system (both derivative operators are skew-symmetric), so its
// drift measures the time integration error.
#pragma once
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "rodcore/scene.hpp"

namespace rodcore {

struct EnergyParts {
  double kinetic_translational = 0.0;  // 1/2 |gamma|^2
  double kinetic_rotational = 0.0;     // 1/2 omega . I omega
  double shear = 0.0;                  // 1/2 [C1 (G1-G01)^2 + C2 (G2-G02)^2]
  double extension = 0.0;              // 1/2 C3 (G3-G03)^2
  double bend = 0.0;                   // 1/2 [D1 (O1-O01)^2 + D2 (O2-O02)^2]
  double twist = 0.0;                  // 1/2 D3 (O3-O03)^2
  double total() const {
    return kinetic_translational + kinetic_rotational + shear + extension + bend + twist;
  }
  std::map<std::string, double> as_map() const;
};

// y: 12 N state; Gamma0, Omega0: 3 N component-major intrinsic shape; h = L/N.
EnergyParts energy_parts(const double* y, std::size_t N, double h, const Material& m,
                         const std::vector<double>& Gamma0, const std::vector<double>& Omega0);

// Index of the first non-finite value in y (n values), or -1.
long first_non_finite(const double* y, std::size_t n);

// Index i of the smallest Gamma3 and its value (folding when <= 0).
std::pair<std::size_t, double> min_Gamma3(const double* y, std::size_t N);

}  // namespace rodcore
