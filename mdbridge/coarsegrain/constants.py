"""Physical constants and unit conversions of the coarse-graining (the SI constants, AMU
included, are dna_models.units': one place for the whole toolkit).

The paper's rod density and inertia (Sec 2.1) come from dna_models.units, so the
comparison uses the same numbers as the solver."""
from __future__ import annotations

import math

from dna_models.units import AMU, ANGSTROM, BOLTZMANN, Units  # noqa: F401 - re-exported for this package

DEG = math.pi / 180.0             # rad per degree


def kT_J(temperature_K: float) -> float:
    return BOLTZMANN * temperature_K


def kT_pN_nm(temperature_K: float) -> float:
    """kT in pN nm (4.14 at 300 K)."""
    return kT_J(temperature_K) * 1e21


def paper_rho_I() -> tuple[float, float]:
    """The paper's rho (kg/m) and I (kg m), Sec 2.1: 3.22e-15 and 8.05e-34."""
    u = Units.paper()
    return u.rho, u.I
