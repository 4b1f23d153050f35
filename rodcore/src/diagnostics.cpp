#include "rodcore/diagnostics.hpp"

#include <cmath>

#include "rodcore/state.hpp"

namespace rodcore {

std::map<std::string, double> EnergyParts::as_map() const {
  return {{"kinetic_translational", kinetic_translational},
          {"kinetic_rotational", kinetic_rotational},
          {"shear", shear},
          {"extension", extension},
          {"bend", bend},
          {"twist", twist}};
}

EnergyParts energy_parts(const double* y, std::size_t N, double h, const Material& m,
                         const std::vector<double>& Gamma0, const std::vector<double>& Omega0) {
  EnergyParts e;
  auto sq = [](double x) { return x * x; };
  const double* G0 = Gamma0.data();
  const double* O0 = Omega0.data();
  for (std::size_t i = 0; i < N; ++i) {
    const double g1 = y[0 * N + i], g2 = y[1 * N + i], g3 = y[2 * N + i];
    const double w1 = y[3 * N + i], w2 = y[4 * N + i], w3 = y[5 * N + i];
    const double dG1 = y[6 * N + i] - G0[i], dG2 = y[7 * N + i] - G0[N + i],
                 dG3 = y[8 * N + i] - G0[2 * N + i];
    const double dO1 = y[9 * N + i] - O0[i], dO2 = y[10 * N + i] - O0[N + i],
                 dO3 = y[11 * N + i] - O0[2 * N + i];
    e.kinetic_translational += sq(g1) + sq(g2) + sq(g3);
    e.kinetic_rotational += m.I[0] * sq(w1) + m.I[1] * sq(w2) + m.I[2] * sq(w3);
    e.shear += m.C[0] * sq(dG1) + m.C[1] * sq(dG2);
    e.extension += m.C[2] * sq(dG3);
    e.bend += m.D[0] * sq(dO1) + m.D[1] * sq(dO2);
    e.twist += m.D[2] * sq(dO3);
  }
  const double f = 0.5 * h;
  e.kinetic_translational *= f;
  e.kinetic_rotational *= f;
  e.shear *= f;
  e.extension *= f;
  e.bend *= f;
  e.twist *= f;
  return e;
}

long first_non_finite(const double* y, std::size_t n) {
  for (std::size_t i = 0; i < n; ++i)
    if (!std::isfinite(y[i])) return static_cast<long>(i);
  return -1;
}

std::pair<std::size_t, double> min_Gamma3(const double* y, std::size_t N) {
  const double* G3 = component(y, N, Gamma, 2);
  std::size_t imin = 0;
  for (std::size_t i = 1; i < N; ++i)
    if (G3[i] < G3[imin]) imin = i;
  return {imin, G3[imin]};
}

}  // namespace rodcore
