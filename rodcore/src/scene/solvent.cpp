#include "rodcore/solvent.hpp"

#include <cmath>
#include <numbers>

#include "rodcore/dna_units.hpp"
#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"

namespace rodcore {

WaterFriction water_friction_SI(double eta, double a, double length) {
  const double p = length / (2.0 * a);
  if (!(p >= 2.0))
    throw InputError("the \"water\" friction needs a rod at least 4 radii long (aspect ratio p = L / 2a = " +
                     message_number(p) +
                     " < 2, where the cylinder formulas stop holding); give the frictions as numbers");
  const double pi = std::numbers::pi;
  const double lp = std::log(p);
  const double nu_par = -0.207 + 0.980 / p - 0.133 / (p * p);
  const double nu_perp = 0.839 + 0.185 / p + 0.233 / (p * p);
  WaterFriction w;
  w.translational = {2.0 * pi * eta / (lp + nu_par), 4.0 * pi * eta / (lp + nu_perp)};
  w.rotational = {4.0 * pi * eta * a * a, pi * eta * a * a};
  return w;
}

WaterFriction water_friction_rod(double viscosity_mPa_s, double radius_nm, double L) {
  const double ell_m = dna_units::ell_A * 1e-10;
  WaterFriction w = water_friction_SI(viscosity_mPa_s * 1e-3, radius_nm * 1e-9, L * ell_m);
  for (double& z : w.translational) z /= dna_units::friction_translational_scale_Pa_s;
  for (double& z : w.rotational) z /= dna_units::friction_rotational_scale_N_s;
  return w;
}

double dna_length_nm() { return dna_units::ell_A / 10.0; }

double kT_rod_of_kelvin(double temperature_K) {
  return dna_units::kB_J_per_K * temperature_K / dna_units::energy_scale_J;
}

}  // namespace rodcore
