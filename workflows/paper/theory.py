"""Closed-form results of the paper used by the figures and checks.

The formulas live in the C++ header rodcore/include/rodcore/analytic.hpp (ONE
place). When the compiled module exposes them (`rodcore.analytic.dispersion`,
`rodcore.analytic.energy_ratio`) they are used. Without the module, Eq (26)/(39)
comes from `mdbridge.analysis.dispersion.omega_pm` (the project's only Python
copy of it) and Eq (27) from the one line below -- so this file adds no second copy
of the dispersion relation.

Conventions (paper Sec 3-4, dimensionless units, C1 = I1 = 1):
  kappa_p = k + Omega03, kappa_m = k - Omega03 (Eq 24; Omega03 = 0 gives Eq 39);
  branch "plus"/"minus" is omega_+/omega_- of Eq (26).
"""
from __future__ import annotations

import numpy as np

D1_PAPER = 1.21       # D rho / (I C), Sec 2.2
C3_PAPER = 1.19       # Eq (8)
BRANCHES = ("plus", "minus")


def _cpp(name):
    try:
        import rodcore  # type: ignore
    except ImportError:
        return None
    return getattr(getattr(rodcore, "analytic", None), name, None)


def _check_branch(branch: str) -> int:
    if branch not in BRANCHES:
        raise ValueError(f"branch must be 'plus' or 'minus', got {branch!r}")
    return +1 if branch == "plus" else -1


def omega(kappa, branch: str, D1: float = D1_PAPER, Gamma03: float = 1.0):
    """Eq (26) (Eq 39 for kappa = k): omega_+ or omega_- at (modified) wavenumber kappa."""
    sign = _check_branch(branch)
    kappa = np.asarray(kappa, float)
    f = _cpp("dispersion")
    if f is not None:
        return np.vectorize(lambda q: f(float(q), D1, Gamma03, sign))(kappa) * 1.0
    return np.asarray(_python_dispersion().omega_pm(kappa, D1, Gamma03, branch), float) * 1.0


def _python_dispersion():
    """mdbridge/analysis/dispersion.py loaded on its own: importing the mdbridge.analysis
    package would pull in MDAnalysis (seconds) for one formula."""
    import importlib.util
    import sys
    name = "mdbridge.analysis.dispersion"
    if name in sys.modules:
        return sys.modules[name]
    from pathlib import Path
    path = Path(__file__).resolve().parents[2] / "mdbridge" / "analysis" / "dispersion.py"
    spec = importlib.util.spec_from_file_location("_dnarod_dispersion", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def modified_wavenumbers(k, Omega03: float):
    """(kappa_p, kappa_m) = (k + Omega03, k - Omega03)."""
    k = np.asarray(k, float)
    return k + Omega03, k - Omega03


def energy_ratio(w, kappa, D1: float = D1_PAPER, Gamma03: float = 1.0):
    """Eq (27): shear / bend elastic energy Gamma_perp^2 / (D1 Omega_perp^2) of the exact wave."""
    f = _cpp("energy_ratio")
    w, kappa = np.broadcast_arrays(np.asarray(w, float), np.asarray(kappa, float))
    if f is not None:
        return np.vectorize(lambda a, b: f(float(a), float(b), D1, Gamma03))(w, kappa) * 1.0
    return (w ** 2 - kappa ** 2 * D1) ** 2 / (D1 * kappa ** 2 * Gamma03 ** 2)


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
