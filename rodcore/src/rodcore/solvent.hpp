// The solvent of the thermal rod's "water" friction (docs/thermal.md): the
// drag per unit length of a cylinder of radius a at viscosity eta, in SI,
// and in the rod's units. Scene layer: it needs the DNA unit system
// (dna_units.hpp, generated from dna_models/units.py).
//
//   translation   along:  2 pi eta / (ln p + nu_par),  across: 4 pi eta / (ln p + nu_perp),
//                 p = L / (2 a), nu_par = -0.207 + 0.980 / p - 0.133 / p^2,
//                 nu_perp = 0.839 + 0.185 / p + 0.233 / p^2: the friction of a
//                 rigid cylinder of length L (Tirado, Lopez Martinez & Garcia
//                 de la Torre, J Chem Phys 81:2047, 1984; valid for p >= 2)
//                 divided by L. L is the length of the motion
//                 (thermal.friction_length_nm), by default the rod's: the
//                 wavelength of a periodic rod's slowest mode (docs/thermal.md).
//   rotation      about the axis:  4 pi eta a^2 (the exact Stokes flow
//                 around a spinning infinite cylinder);
//                 across the axis: pi eta a^2 (the exact Stokes flow u_3 =
//                 w a^2 sin(phi) / r of an infinite cylinder whose cross
//                 sections all turn about parallel transverse axes, i.e. shear
//                 the rod; derived in docs/thermal.md).
#pragma once
#include <array>

namespace rodcore {

struct WaterFriction {
  std::array<double, 2> translational;  // [along, across] per length
  std::array<double, 2> rotational;     // [about the axis, across] per length
};

// SI: Pa s (N s / m^2) and N s (N m s / m). Throws InputError if p < 2.
WaterFriction water_friction_SI(double viscosity_Pa_s, double radius_m, double length_m);
// Rod units, for a motion of dimensionless length L (viscosity in mPa s, radius in nm).
WaterFriction water_friction_rod(double viscosity_mPa_s, double radius_nm, double L);
// The rod's length unit in nm (dna_units.hpp: ell).
double dna_length_nm();
// k_B T in the rod's energy unit (C l) at temperature T [K].
double kT_rod_of_kelvin(double temperature_K);

}  // namespace rodcore
