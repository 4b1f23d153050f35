"""Closed-form results of the paper used by the figures and checks.

The dispersion relation (Eqs 26/39) and the energy ratio (Eq 27) live in the C++
header rodcore/src/rodcore/analytic.hpp (ONE place) and are called here through
the compiled module (`rodcore.analytic`). The other closed forms below (Eqs 25, 37-38,
40-45 and the paper's limits) have no C++ counterpart and are written once here.

Conventions (paper Sec 3-4, dimensionless units, C1 = I1 = 1):
  kappa_p = k + Omega03, kappa_m = k - Omega03 (Eq 24; Omega03 = 0 gives Eq 39);
  branch "plus"/"minus" is omega_+/omega_- of Eq (26).
"""
from __future__ import annotations

import numpy as np

from dna_models.units import Units
from mdbridge.rod.run import analytic

D1_PAPER = Units.paper().D_star[0]   # D rho / (I C) = 1.21, Sec 2.2 (dna_models)
C3_PAPER = Units.paper().C_star[2]   # 1.19, Eq (8) (dna_models)
BRANCHES = ("plus", "minus")


def _check_branch(branch: str) -> int:
    if branch not in BRANCHES:
        raise ValueError(f"branch must be 'plus' or 'minus', got {branch!r}")
    return +1 if branch == "plus" else -1


def omega(kappa, branch: str, D1: float = D1_PAPER, Gamma03: float = 1.0):
    """Eq (26) (Eq 39 for kappa = k): omega_+ or omega_- at (modified) wavenumber kappa."""
    sign = _check_branch(branch)
    f = analytic().dispersion
    return np.vectorize(lambda q: f(float(q), D1, Gamma03, sign), otypes=[float])(np.asarray(kappa, float)) * 1.0


def modified_wavenumbers(k, Omega03: float):
    """(kappa_p, kappa_m) = (k + Omega03, k - Omega03)."""
    k = np.asarray(k, float)
    return k + Omega03, k - Omega03


def energy_ratio(w, kappa, D1: float = D1_PAPER, Gamma03: float = 1.0):
    """Eq (27): shear / bend elastic energy Gamma_perp^2 / (D1 Omega_perp^2) of the exact wave."""
    f = analytic().energy_ratio
    w, kappa = np.broadcast_arrays(np.asarray(w, float), np.asarray(kappa, float))
    return np.vectorize(lambda a, b: f(float(a), float(b), D1, Gamma03), otypes=[float])(w, kappa) * 1.0


def shear_bend_amplitude_ratio(w, k, D1: float = D1_PAPER, Gamma03: float = 1.0):
    """Fig 5: |Gamma1| / |Omega2| of the untwisted-rod wave, Eqs (40)-(43).

    Eq (43) / Eq (41): |(w^2 - D1 k^2) / (w Gamma03)| / |k / w| = |w^2 - D1 k^2| / (k Gamma03).
    (Its square over D1 is Eq 27 at kappa = k: the two figures say the same thing.)
    """
    w, k = np.asarray(w, float), np.asarray(k, float)
    return np.abs(w ** 2 - D1 * k ** 2) / (np.abs(k) * Gamma03)


def dispersion_residual(w, kappa, D1: float = D1_PAPER, Gamma03: float = 1.0):
    """Eq (25): (w^2 - kappa^2 D1)(w^2 - kappa^2) - w^2 Gamma03^2 (zero on every branch)."""
    w, kappa = np.asarray(w, float), np.asarray(kappa, float)
    return (w ** 2 - kappa ** 2 * D1) * (w ** 2 - kappa ** 2) - w ** 2 * Gamma03 ** 2


def second_harmonic_amplitude(w, k, a, Gamma03: float = 1.0, C3: float = C3_PAPER,
                              C3_power: int = 1):
    """Amplitude of delta Gamma3 = Q cos 2(w t - k s) forced by the first-order wave of
    amplitude a (Eqs 37-38, 45): Q = -Gamma03 a^2 / (4 (w^2 - k^2 C3^C3_power)).
    C3_power = 1 is what Eqs (37)-(38) give (docs/numerics.md); 2 is Eq (45) as printed."""
    return -Gamma03 * np.asarray(a, float) ** 2 / (4.0 * (np.asarray(w) ** 2 - np.asarray(k) ** 2 * C3 ** C3_power))


# -- asymptotic limits stated in the paper (Secs 3.1 and 4.1) ---------------------------------
def limit_small_kappa(kappa, branch: str, D1: float = D1_PAPER, Gamma03: float = 1.0):
    """k -> 0 (Sec 4.1) and kappa_m -> 0 (Sec 3.1): omega_+ ~ Gamma03 + kappa^2 (D1+1) / (2 Gamma03),
    omega_- ~ kappa^2 sqrt(D1) / Gamma03."""
    kappa = np.asarray(kappa, float)
    if _check_branch(branch) > 0:
        return Gamma03 + kappa ** 2 * (D1 + 1.0) / (2.0 * Gamma03)
    return kappa ** 2 * np.sqrt(D1) / Gamma03


def limit_large_kappa(kappa, branch: str, D1: float = D1_PAPER):
    """k -> infinity (Secs 3.1, 4.1): omega_+ ~ sqrt(D1) |kappa| (bend), omega_- ~ |kappa| (shear),
    for D1 > 1."""
    kappa = np.abs(np.asarray(kappa, float))
    return np.sqrt(D1) * kappa if _check_branch(branch) > 0 else kappa
