"""The one place where physical and dimensionless rod units meet (Sec 2.2).

The paper scales time by tau = sqrt(I/C) and length by l = sqrt(I/rho)
(Eq 15 and the text after it), so that C* = C/C and D* = (D rho / I C) D/D.
Every conversion in dnarod goes through `Units`; the C++ solver receives the
same numbers through a header generated from this module at build time
(`python3 -m dna_models.units --cpp-header OUT`), so they cannot diverge.
"""
from __future__ import annotations

import argparse
import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

DATA = Path(__file__).resolve().parent / "data" / "dna_elastic_constants.toml"

ANGSTROM = 1e-10  # m
PICOSECOND = 1e-12  # s
ANGSTROM_PER_NM = 10.0  # GROMACS lengths are nm, dnarod's Angstrom
BOLTZMANN = 1.380649e-23  # J/K (exact, SI 2019)
AVOGADRO = 6.02214076e23  # 1/mol (exact, SI 2019)
AMU = 1.66053906660e-27       # kg (CODATA 2018)
BOLTZMANN_KJ_PER_MOL_K = BOLTZMANN * AVOGADRO / 1000.0  # GROMACS's k_B (R), kJ/(mol K)


def persistence_length_nm(D_J_m: float, temperature_K: float) -> float:
    """Bend persistence length D / (k_B T) [nm] of a bend stiffness D [J m]."""
    return D_J_m / (BOLTZMANN * temperature_K) * 1e9


@dataclass(frozen=True)
class Units:
    """Scales and dimensionless material of the paper's DNA rod."""

    rho: float  # kg/m
    I: float    # kg m
    C: float    # N
    D: float    # kg m^3 / s^2
    I_ratios: tuple
    C_ratios: tuple
    D_ratios: tuple
    rise_A: float
    bend_shear_ratio: float  # D rho / (I C) as printed in Sec 2.2 (1.21)
    bp_per_turn_paper: float  # 158 bp in 15 turns (Sec 6): the paper's uniform twist

    @classmethod
    def paper(cls, path: Path = DATA) -> "Units":
        with open(path, "rb") as f:
            d = tomllib.load(f)
        p = d["paper_2_1"]
        return cls(rho=p["rho"], I=p["I"], C=p["C"], D=p["D"],
                   I_ratios=tuple(p["I_ratios"]), C_ratios=tuple(p["C_ratios"]),
                   D_ratios=tuple(p["D_ratios"]), rise_A=d["b_dna"]["rise_A"],
                   bend_shear_ratio=p["bend_shear_ratio_printed"],
                   bp_per_turn_paper=d["b_dna"]["bp_per_turn_paper"])

    # -- scales (Sec 2.2) -------------------------------------------------
    @property
    def tau_s(self) -> float:
        """Time scale tau = sqrt(I/C) [s] (paper: 9.4e-13 s)."""
        return math.sqrt(self.I / self.C)

    @property
    def ell_m(self) -> float:
        """Length scale l = sqrt(I/rho) [m] (paper: 5.0e-10 m)."""
        return math.sqrt(self.I / self.rho)

    @property
    def tau_ps(self) -> float:
        return self.tau_s / PICOSECOND

    @property
    def ell_A(self) -> float:
        return self.ell_m / ANGSTROM

    @property
    def velocity_A_per_ps(self) -> float:
        """One dimensionless velocity gamma* in Angstrom/ps."""
        return self.ell_A / self.tau_ps

    # -- dimensionless material (Eq 15) ----------------------------------
    @property
    def bend_shear_ratio_from_constants(self) -> float:
        """D rho / (I C) from the Sec 2.1 constants (1.2115; printed as 1.21)."""
        return self.D * self.rho / (self.I * self.C)

    @property
    def C_star(self) -> tuple:
        return tuple(float(c) for c in self.C_ratios)

    @property
    def D_star(self) -> tuple:
        return tuple(self.bend_shear_ratio * d for d in self.D_ratios)

    @property
    def I_star(self) -> tuple:
        return tuple(float(i) for i in self.I_ratios)

    # -- conversions -------------------------------------------------------
    def length_to_rod(self, x_A):
        return x_A / self.ell_A

    def length_to_A(self, x):
        return x * self.ell_A

    def time_to_rod(self, t_ps):
        return t_ps / self.tau_ps

    def time_to_ps(self, t):
        return t * self.tau_ps

    def velocity_to_rod(self, v_A_per_ps):
        return v_A_per_ps / self.velocity_A_per_ps

    def velocity_to_A_per_ps(self, v):
        return v * self.velocity_A_per_ps

    def angular_velocity_to_rad_per_ps(self, w):
        """omega = omega* / tau."""
        return w / self.tau_ps

    def curvature_to_rod(self, k_rad_per_A):
        """Omega* = l Omega."""
        return k_rad_per_A * self.ell_A

    # -- energy, stiffness and mass (the dimensionless energy is E / (C l)) ---
    @property
    def energy_scale_J(self) -> float:
        """Energy unit of the rod, C l [J]: the dimensionless energy density is
        e / C (Eq 15), so an energy E [J] of a rod piece is E / (C l)."""
        return self.C * self.ell_m

    def kT_to_rod(self, temperature_K):
        """k_B T in the rod's energy unit."""
        return BOLTZMANN * temperature_K / self.energy_scale_J

    @property
    def friction_translational_scale_Pa_s(self) -> float:
        """One rod unit of translational friction per length, C tau / l^2 [Pa s = N s / m^2]:
        rho dgamma/dt = ... - zeta gamma becomes dimensionless with zeta* = zeta l^2 / (C tau)."""
        return self.C * self.tau_s / self.ell_m**2

    @property
    def friction_rotational_scale_N_s(self) -> float:
        """One rod unit of rotational friction per length, C tau [N s = N m s / m]:
        I domega/dt = ... - zeta_r omega becomes dimensionless with zeta_r* = zeta_r / (C tau)."""
        return self.C * self.tau_s

    def stiffness_to_SI(self, K_star):
        """(..., 6, 6) dimensionless K* -> the stiffness per unit length on (Gamma [1],
        Omega [rad/m]) in SI (N, N m, N m^2 blocks): K = S K* S C with
        S = diag(1, 1, 1, l, l, l), because Omega* = l Omega and the dimensionless energy
        density is e / C."""
        import numpy as np
        s = np.array([1.0, 1.0, 1.0, self.ell_m, self.ell_m, self.ell_m])
        return np.asarray(K_star, dtype=float) * s[:, None] * s[None, :] * self.C

    def mass_amu_per_length_A_to_rod(self, m_amu, h_A):
        """rho* of a mass m [amu] spread over a length h [A] (rho* = rho / rho_paper)."""
        return m_amu * AMU / (h_A * ANGSTROM) / self.rho

    def inertia_amu_A2_per_length_A_to_rod(self, I_amu_A2, h_A):
        """I* of a moment of inertia I [amu A^2] spread over a length h [A] (I* = I / I_paper)."""
        return I_amu_A2 * AMU * ANGSTROM**2 / (h_A * ANGSTROM) / self.I

    def as_dict(self) -> dict:
        return {"tau_ps": self.tau_ps, "ell_A": self.ell_A,
                "velocity_A_per_ps": self.velocity_A_per_ps,
                "C_star": list(self.C_star), "D_star": list(self.D_star),
                "I_star": list(self.I_star), "rise_A": self.rise_A,
                "source": "paper Sec 2.1-2.2, dna_models/data/dna_elastic_constants.toml"}


def cpp_header(u: Units) -> str:
    """The same numbers for the C++ solver (generated, never edited by hand)."""
    def arr(v):
        return "{" + ", ".join(repr(float(x)) for x in v) + "}"
    return f"""// Generated by `python3 -m dna_models.units --cpp-header` from
// dna_models/data/dna_elastic_constants.toml. Do not edit.
#pragma once
#include <array>
namespace rodcore::dna_units {{
inline constexpr double tau_ps = {u.tau_ps!r};            // time scale sqrt(I/C)
inline constexpr double ell_A = {u.ell_A!r};              // length scale sqrt(I/rho)
inline constexpr double velocity_A_per_ps = {u.velocity_A_per_ps!r};
inline constexpr double rise_A = {u.rise_A!r};
inline constexpr std::array<double, 3> C_star = {arr(u.C_star)};
inline constexpr std::array<double, 3> D_star = {arr(u.D_star)};
inline constexpr std::array<double, 3> I_star = {arr(u.I_star)};
// The thermal rod (docs/thermal.md): kT = kB_J_per_K T / energy_scale_J;
// a friction per length in SI divided by its scale is the rod's.
inline constexpr double kB_J_per_K = {BOLTZMANN!r};
inline constexpr double energy_scale_J = {u.energy_scale_J!r};    // C l
inline constexpr double friction_translational_scale_Pa_s = {u.friction_translational_scale_Pa_s!r};  // C tau / l^2
inline constexpr double friction_rotational_scale_N_s = {u.friction_rotational_scale_N_s!r};  // C tau
}}  // namespace rodcore::dna_units
"""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cpp-header", metavar="OUT", help="write the C++ header")
    args = ap.parse_args(argv)
    u = Units.paper()
    if args.cpp_header:
        text = cpp_header(u)
        out = Path(args.cpp_header)
        out.parent.mkdir(parents=True, exist_ok=True)
        if not out.exists() or out.read_text() != text:
            out.write_text(text)
    else:
        for k, v in u.as_dict().items():
            print(f"{k} = {v}")


if __name__ == "__main__":
    main()
