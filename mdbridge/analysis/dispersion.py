"""Linear dispersion of bend-shear waves (paper Eqs 25-26 and 39), in one place.

For an isotropic rod (C1 = C2, D1 = D2) the intrinsic twist Omega03 does not change the
transverse dynamics seen in the laboratory frame at linear order: the body-frame solution
of Eq (24) at body wavenumber k is a laboratory wave of the modified wavenumber
kappa = k +- Omega03, and its frequency, Eq (26), is Eq (39) of the untwisted rod at
wavenumber kappa. A planar laboratory wave of wavenumber kappa is the sum of the two
circular polarisations (kappa_p and kappa_m branches) with the same |kappa|, hence the
same frequency -- which is why the planar DNA scene stays planar. So the laboratory
phase speed of the mode with laboratory wavenumber kappa (dimensionless) is

    c_pm = omega_pm(kappa) / kappa,
    omega_pm = 1/2 [ sqrt(kappa^2 (sqrt D1 + 1)^2 + G^2) pm sqrt(kappa^2 (sqrt D1 - 1)^2 + G^2) ],

with G = Gamma03 (Eq 39; C1 = 1 in the paper's scaling). omega_- is the bend (flexural)
branch, omega_+ the shear branch. Here kappa is per unit FIDUCIAL arclength; the
laboratory length of the rod is Gamma03 L, so a speed along the laboratory axis is
Gamma03 omega / kappa (in l / tau).

The formula's one home is rodcore/src/analytic.cpp (`analytic::dispersion`); Python calls
it through the compiled module (`rodcore.analytic.dispersion(kappa, D1, Gamma03, +1|-1)`).
"""
from __future__ import annotations

import numpy as np

from dna_models.units import Units, persistence_length_nm


def omega_pm(kappa, D1: float, Gamma03: float, branch: str = "minus"):
    """Eq (39)/(26): frequency of the bend-shear branch `branch` ('plus' or 'minus'),
    element-wise over kappa, by the C++ closed form rodcore.analytic.dispersion."""
    if branch not in ("plus", "minus"):
        raise ValueError(f"branch must be 'plus' or 'minus', got {branch!r}")
    from mdbridge.rod.run import analytic
    f = analytic().dispersion
    sign = 1 if branch == "plus" else -1
    return np.vectorize(lambda q: f(float(q), float(D1), float(Gamma03), sign), otypes=[float])(kappa) * 1.0


def lab_speed_A_per_ps(length_fiducial: float, D1: float, Gamma03: float, branch="minus",
                       mode: int = 1, units: Units | None = None) -> float:
    """Laboratory phase speed [A/ps] of Fourier mode `mode` of a periodic rod of fiducial
    length `length_fiducial` (dimensionless) in the small-amplitude limit."""
    u = units or Units.paper()
    kappa = 2 * np.pi * mode / length_fiducial
    c = Gamma03 * float(omega_pm(kappa, D1, Gamma03, branch)) / kappa
    return u.velocity_to_A_per_ps(c)


def lab_speed_material_A_per_ps(length_fiducial: float, C1: float, D1: float, I1: float, rho: float,
                                Gamma03: float = 1.0, branch: str = "minus", mode: int = 1,
                                units: Units | None = None) -> float:
    """`lab_speed_A_per_ps` for a rod whose shear C1, bend D1, inertia I1 and density rho (all
    in the paper's units) are not the paper's 1, D1, 1, 1: Eq (39) in the units of that rod
    (force C1, length sqrt(I1 / rho), time sqrt(I1 / C1)), where it takes the paper's form
    with D1' = D1 rho / (I1 C1) and kappa' = kappa sqrt(I1 / rho). Written out, this is the
    Timoshenko quartic I1 rho w^4 - w^2 (rho D1 k^2 + rho C1 + I1 C1 k^2) + C1 D1 k^4 = 0
    (Gamma03 = 1), which tests/python/test_coarsegrain_loop.py checks."""
    u = units or Units.paper()
    kappa = 2 * np.pi * mode / length_fiducial
    Dp = D1 * rho / (I1 * C1)
    w = float(omega_pm(kappa * np.sqrt(I1 / rho), Dp, Gamma03, branch)) / np.sqrt(I1 / C1)
    return u.velocity_to_A_per_ps(Gamma03 * w / kappa)


def bend_modulus_for_speed(speed_A_per_ps: float, length_fiducial: float, Gamma03: float,
                           units: Units | None = None, D1_bounds=(1e-4, 1e4)) -> dict:
    """The bend stiffness that makes the rod's bend-branch speed equal a measured speed
    (e.g. the MD's), other constants fixed: D1* solving lab_speed(D1*) = speed, and the
    physical D = D1* I C / rho [J m] (Eq 15 with the paper's scales) and the persistence
    length D / kT at 300 K."""
    from scipy.optimize import brentq
    u = units or Units.paper()
    f = lambda d: lab_speed_A_per_ps(length_fiducial, d, Gamma03, "minus", 1, u) - speed_A_per_ps  # noqa: E731
    lo, hi = D1_bounds
    if f(lo) * f(hi) > 0:
        return {"D1_star": float("nan"), "reason": "speed outside the bend branch's range"}
    D1 = brentq(f, lo, hi, xtol=1e-12)
    D = D1 * u.I * u.C / u.rho
    return {"D1_star": D1, "D_J_m": D, "D_over_paper": D1 / u.D_star[0],
            "persistence_length_nm_300K": persistence_length_nm(D, 300.0)}


def omega_pm_tension(kappa, D1: float, Gamma3: float, n3: float, branch: str = "minus"):
    """Eq (39) generalised to a straight rod held at Gamma3 under the axial force n3
    (dimensionless, units of C; n3 = C3 (Gamma3 - Gamma03) of the rod's own intrinsic Gamma03).
    Linearising the planar polarisation (gamma1, Gamma1, omega2, Omega2) about that state
    adds Omega2 n3 to the force balance (Eq 33) and -Gamma1 n3 to the moment balance (Eq 34),
    giving  (w^2 - D1 k^2)(w^2 - k^2) = (G - n3)(G w^2 - n3 k^2),  G = Gamma3, which is the
    paper's consistency condition for n3 = 0. The bend branch vanishes at the Euler load
    n3 = -D1 k^2 / (G - n3) (`critical_compression`)."""
    k2 = np.asarray(kappa, float) ** 2
    G, T = float(Gamma3), float(n3)
    b = D1 * k2 + k2 + G * (G - T)
    c = D1 * k2 ** 2 + (G - T) * T * k2
    disc = np.sqrt(np.maximum(b * b - 4 * c, 0.0))
    if branch == "plus":
        return np.sqrt(0.5 * (b + disc))
    if branch == "minus":
        x = 0.5 * (b - disc)
        return np.where(x >= 0, np.sqrt(np.abs(x)), np.nan)
    raise ValueError(f"branch must be 'plus' or 'minus', got {branch!r}")


def critical_compression(length_fiducial: float, D1: float, C3: float, mode: int = 1) -> dict:
    """Axial strain and force (dimensionless) at which the bend branch of the fundamental of
    a closed rod vanishes (buckling), from `omega_pm_tension` with n3 = C3 (Gamma3 - 1):
    solves D1 k^2 + (G - n3) n3 = 0 for the strain e = G - 1 < 0."""
    from scipy.optimize import brentq
    k2 = (2 * np.pi * mode / length_fiducial) ** 2
    f = lambda e: D1 * k2 + ((1 + e) - C3 * e) * C3 * e  # noqa: E731
    e = brentq(f, -0.5, 0.0)
    return {"strain": float(e), "n3": float(C3 * e)}
