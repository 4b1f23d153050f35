"""Elastic-constant presets for the DNA rod.

* `paper()`: the paper's DNA (Sec 2.1: C = 9.08e-10 N, C3 = 1.19 C,
  D = 2.75e-28 J m, D3 = 1.67 D, I, rho), read through dna_models.units.
* `olson1998()`: stiffness of a sequence-averaged DNA step from Olson et al.
  1998 PNAS 95:11163 (protein-DNA crystal complexes), data in
  dna_models/data/olson1998_average.toml. A step of length h = mean rise with
  energy 1/2 F_k d_k^2 per component equals a rod piece of length h with energy
  1/2 K (d_k / h)^2 h, so the rod constant is K = h F_k: bend/twist stiffness
  D_k = h F_k (180/pi)^2 kT (J m) for tilt (D1), roll (D2), twist (D3), and
  shear/stretch stiffness C_k = h F_k kT (N) for shift (C1), slide (C2), rise
  (C3). Only the diagonal is used (the rod has diagonal C and D); the
  off-diagonal couplings (largest: slide-rise, twist-rise) are dropped. Mass
  density and moment of inertia come from the paper (they are geometry, not
  statistics). Note that Olson's roll stiffness gives D2 = 2.7e-28 J m, the
  paper's D, while its stretch stiffness (C3 ~ 3200 pN) is ~3x the paper's 1087 pN.

Dimensionless values use the paper's scales (Eq 15): C* = C / C_paper and
D* = D rho / (I C_paper), so a preset only changes the material, never the units.
"""
from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass
from pathlib import Path

from .units import ANGSTROM, BOLTZMANN, Units

DATA = Path(__file__).resolve().parent / "data"


@dataclass(frozen=True)
class ElasticPreset:
    name: str
    C: tuple       # shear, shear, stretch stiffness [N]
    D: tuple       # bend, bend, twist stiffness [J m]
    I: tuple       # moment of inertia density [kg m]
    rho: float     # mass density [kg/m]
    source: str
    star: dict | None = None   # dimensionless values to use instead of the computed ones

    def dimensionless(self, units: Units | None = None) -> dict:
        """C*, D*, I* in the paper's unit system (Eq 15)."""
        if self.star is not None and units is None:
            return dict(self.star)
        u = Units.paper() if units is None else units
        return {"C_star": tuple(c / u.C for c in self.C),
                "D_star": tuple(d * u.rho / (u.I * u.C) for d in self.D),
                "I_star": tuple(i / u.I for i in self.I)}


def paper() -> ElasticPreset:
    u = Units.paper()
    return ElasticPreset(
        name="paper", C=tuple(u.C * r for r in u.C_ratios), D=tuple(u.D * r for r in u.D_ratios),
        I=tuple(u.I * r for r in u.I_ratios), rho=u.rho,
        source="paper Sec 2.1 (dna_models/data/dna_elastic_constants.toml)",
        # the solver's material: D* with the printed 1.21 (the constants give 1.2115)
        star={"C_star": u.C_star, "D_star": u.D_star, "I_star": u.I_star})


def olson1998_table(path: Path = DATA / "olson1998_average.toml") -> dict:
    with open(path, "rb") as f:
        return tomllib.load(f)


def olson1998() -> ElasticPreset:
    d = olson1998_table()
    F = d["force_constants_diagonal"]
    h_A = d["step_means"]["rise"]
    kT = BOLTZMANN * d["thermal"]["temperature_K"]
    per_rad2 = (180.0 / math.pi) ** 2
    D = tuple(h_A * ANGSTROM * F[k] * per_rad2 * kT for k in ("tilt", "roll", "twist"))
    C = tuple(h_A * F[k] * kT / ANGSTROM for k in ("shift", "slide", "rise"))
    u = Units.paper()
    return ElasticPreset(name="olson1998", C=C, D=D, I=tuple(u.I * r for r in u.I_ratios), rho=u.rho,
                         source="Olson et al. 1998 PNAS 95:11163, sequence average "
                                "(dna_models/data/olson1998_average.toml)")
