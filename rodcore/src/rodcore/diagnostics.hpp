// Diagnostics of a rod state (paper Appendix A). The energy
//   E = 1/2 int_0^L { rho |gamma|^2 + omega.I omega + e.K e } ds,
//   e = (Gamma - Gamma0, Omega - Omega0)
// (for K = diag(C, D): the paper's C and D terms)
// is evaluated with the periodic trapezoid rule h sum_i (spectrally accurate
// for smooth periodic integrands). It is conserved exactly by the
// semi-discrete system (both derivative operators are skew-symmetric), so its
// drift measures the time integration error.
#pragma once
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "rodcore/material.hpp"
#include "rodcore/scene.hpp"

namespace rodcore {

struct EnergyParts {
  double kinetic_translational = 0.0;  // 1/2 rho |gamma|^2
  double kinetic_rotational = 0.0;     // 1/2 omega . I omega (all of I, off-diagonals included)
  double shear = 0.0;                  // 1/2 [K11 e1^2 + K22 e2^2]   (K11 = C1, ...)
  double extension = 0.0;              // 1/2 K33 e3^2
  double bend = 0.0;                   // 1/2 [K44 e4^2 + K55 e5^2]   (K44 = D1, ...)
  double twist = 0.0;                  // 1/2 K66 e6^2
  double coupling = 0.0;               // sum_{r<c} K_rc e_r e_c: the off-diagonal terms of K
  bool coupled = false;                // the material has off-diagonal K (then as_map has "coupling")
  double contact = 0.0;                // self-contact (contact.hpp), set by the caller
  bool has_contact = false;            // the scene has [contact] (then as_map has "contact")
  double total() const {
    return kinetic_translational + kinetic_rotational + shear + extension + bend + twist + coupling + contact;
  }
  std::map<std::string, double> as_map() const;
};

// y: 12 N state; Gamma0, Omega0: 3 N component-major intrinsic shape; h = L/N.
EnergyParts energy_parts(const double* y, std::size_t N, double h, const MaterialField& m,
                         const std::vector<double>& Gamma0, const std::vector<double>& Omega0);
// The same for a scene's Material (validated and resolved first).
EnergyParts energy_parts(const double* y, std::size_t N, double h, const Material& m,
                         const std::vector<double>& Gamma0, const std::vector<double>& Omega0);

// Index of the first non-finite value in y (n values), or -1.
long first_non_finite(const double* y, std::size_t n);

// Index i of the smallest Gamma3 and its value (folding when <= 0).
std::pair<std::size_t, double> min_Gamma3(const double* y, std::size_t N);

}  // namespace rodcore
