// The planar invariant subspace of an intrinsically straight, untwisted rod
// (paper Sec 4.1, Eqs 40-45): with Gamma0 = (0, 0, Gamma03), Omega0 = 0 and
// diagonal C, D, I, a state whose only non-zero components are
//   gamma1, gamma3, omega2, Gamma1, Gamma3, Omega2
// stays in that set (every term of Eqs 11-14 that feeds the other six rows is
// a product containing one of them). A coupled material keeps it only if K and
// I do not couple the kept components to the others (planar_material_coupling). The other polarisation,
// bending about d1 instead of d2 (gamma2, gamma3, omega1, Gamma2, Gamma3, Omega1 non-zero), is invariant for
// the same reason. Integrating only those six rows halves the state; the physics is NOT re-implemented:
// PlanarRHS calls RodRHS::reduced, the same kernel instantiated with the other six rows fixed at zero at
// compile time (their terms vanish, their outputs are not formed). While a PlanarRHS exists, RodRHS's full
// evaluation also skips the derivative of the zero rows (set_nonzero_rows).
#pragma once
#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "rodcore/material.hpp"
#include "rodcore/rhs.hpp"
#include "rodcore/scene.hpp"
#include "rodcore/state.hpp"

namespace rodcore {

// Which of the two planar polarisations: the non-zero bending rate.
enum class Planar { omega2, omega1 };

// State rows kept by the reduced system, in the order of the reduced state
// (polarisation omega2; the next two arrays are the omega1 polarisation).
inline constexpr std::array<int, 6> kPlanarRows = {row(gamma, 0), row(gamma, 2), row(omega, 1),
                                                   row(Gamma, 0), row(Gamma, 2), row(Omega, 1)};
// The six rows that stay exactly zero.
inline constexpr std::array<int, 6> kPlanarZeroRows = {row(gamma, 1), row(omega, 0), row(omega, 2),
                                                       row(Gamma, 1), row(Omega, 0), row(Omega, 2)};
inline constexpr std::array<int, 6> kPlanarRows1 = {row(gamma, 1), row(gamma, 2), row(omega, 0),
                                                    row(Gamma, 1), row(Gamma, 2), row(Omega, 0)};
inline constexpr std::array<int, 6> kPlanarZeroRows1 = {row(gamma, 0), row(omega, 1), row(omega, 2),
                                                        row(Gamma, 0), row(Omega, 1), row(Omega, 2)};

// "omega2" / "omega1" (the name a checkpoint records), and back (nullopt: neither).
const char* planar_name(Planar p);
std::optional<Planar> planar_from_name(const std::string& name);

const std::array<int, 6>& planar_rows(Planar p);
const std::array<int, 6>& planar_zero_rows(Planar p);

// The rod allows the reduction: uniform intrinsic shape Gamma0 = (0, 0, G03),
// Omega0 = (0, 0, 0).
bool planar_reduction_allowed(const Rod& rod);

// Empty if the (uniform) material keeps polarisation p invariant, else why
// not. For omega2 the kept strains are Gamma1, Gamma3, Omega2: a K entry that
// couples one of them to Gamma2, Omega1 or Omega3 gives the zero rows a
// source (e.g. n2 = K21 Gamma1 != 0 drives gamma2), and so does an I with
// I21 or I23 != 0 (omega x I omega and I^-1 leave the omega2 axis). The omega1
// polarisation likewise with the roles of the axes 1 and 2 exchanged.
std::string planar_material_coupling(const MaterialField& mf, Planar p);

// Every component of the six zero rows of y (12 N values) is exactly 0.
bool in_planar_subspace(const double* y, std::size_t N, Planar p = Planar::omega2);

// The polarisation y lies in (omega2 first if both, e.g. at rest), or none.
// Exact zeros: a tiny out-of-plane component means "not planar".
std::optional<Planar> planar_polarisation(const double* y, std::size_t N);

class PlanarRHS {
 public:
  // `full` must outlive this object; it is told to skip the zero rows'
  // derivatives while this object exists.
  explicit PlanarRHS(RodRHS& full, Planar p = Planar::omega2);
  ~PlanarRHS();
  PlanarRHS(const PlanarRHS&) = delete;
  PlanarRHS& operator=(const PlanarRHS&) = delete;

  std::size_t size() const { return 6 * N_; }
  const std::array<int, 6>& rows() const { return rows_; }
  // f6 = the kept rows of RodRHS(expand(y6)).
  void operator()(const double* y6, double* f6) const;
  // 6 N reduced state <-> 12 N full state (zero rows = 0).
  void expand(const double* y6, double* y12) const;
  void reduce(const double* y12, double* y6) const;

 private:
  RodRHS& full_;
  std::size_t N_;
  std::array<int, 6> rows_;
};

}  // namespace rodcore
