#include "rodcore/diagnostics.hpp"

#include <cmath>

#include "rodcore/state.hpp"

namespace rodcore {

std::map<std::string, double> EnergyParts::as_map() const {
  std::map<std::string, double> out{{"kinetic_translational", kinetic_translational},
                                    {"kinetic_rotational", kinetic_rotational},
                                    {"shear", shear},
                                    {"extension", extension},
                                    {"bend", bend},
                                    {"twist", twist}};
  if (coupled) out["coupling"] = coupling;
  if (has_contact) out["contact"] = contact;
  return out;
}

EnergyParts energy_parts(const double* y, std::size_t N, double h, const MaterialField& m,
                         const std::vector<double>& Gamma0, const std::vector<double>& Omega0) {
  EnergyParts e;
  const double* G0 = Gamma0.data();
  const double* O0 = Omega0.data();
  double K[36], I[9];
  m.K_at(0, K);
  m.I_at(0, I);
  const bool per_point = m.kind == MaterialKind::per_point;
  for (int r = 0; r < 6; ++r)
    for (int c = r + 1; c < 6; ++c) e.coupled = e.coupled || (per_point ? true : K[r * 6 + c] != 0.0);
  for (std::size_t i = 0; i < N; ++i) {
    if (per_point) {
      m.K_at(i, K);
      m.I_at(i, I);
    }
    const double rho = m.rho_at(i);
    const double g[3] = {y[0 * N + i], y[1 * N + i], y[2 * N + i]};
    const double w[3] = {y[3 * N + i], y[4 * N + i], y[5 * N + i]};
    double d[6];
    for (int c = 0; c < 3; ++c) {
      d[c] = y[(6 + c) * N + i] - G0[c * N + i];
      d[3 + c] = y[(9 + c) * N + i] - O0[c * N + i];
    }
    e.kinetic_translational += rho * (g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
    // Summed per point first: for a diagonal I the same sum as the paper's
    // I1 w1^2 + I2 w2^2 + I3 w3^2 (adding the zero terms is exact).
    double kr = 0.0;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) kr += I[r * 3 + c] * (w[r] * w[c]);
    e.kinetic_rotational += kr;
    e.shear += K[0] * (d[0] * d[0]) + K[7] * (d[1] * d[1]);
    e.extension += K[14] * (d[2] * d[2]);
    e.bend += K[21] * (d[3] * d[3]) + K[28] * (d[4] * d[4]);
    e.twist += K[35] * (d[5] * d[5]);
    for (int r = 0; r < 6; ++r)
      for (int c = r + 1; c < 6; ++c) e.coupling += 2.0 * K[r * 6 + c] * d[r] * d[c];
  }
  const double f = 0.5 * h;
  e.kinetic_translational *= f;
  e.kinetic_rotational *= f;
  e.shear *= f;
  e.extension *= f;
  e.bend *= f;
  e.twist *= f;
  e.coupling *= f;
  return e;
}

EnergyParts energy_parts(const double* y, std::size_t N, double h, const Material& m,
                         const std::vector<double>& Gamma0, const std::vector<double>& Omega0) {
  return energy_parts(y, N, h, resolve_material(m, N), Gamma0, Omega0);
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
