"""One m-step segment as a piece of uniform rod: its dimensionless material from the
segment's ensemble (the coarse-graining's params.json, params.py). The per-step,
sequence-dependent map with the exact strains and the Jacobian stiffness is
mdbridge/rod/material/steps_to_rod.py; this one is its uniform, small-strain form.

A segment of mean length L with stiffness M = kT <dq dq^T>^-1 (q in A and rad) is a
rod piece with strain Gamma - Gamma0 = dq_translation / L and curvature/twist
Omega - Omega0 = dq_angle / L, energy (L / 2) x^T (L M) x, so the rod's 6 x 6 stiffness
on (Gamma1, Gamma2, Gamma3, Omega1, Omega2, Omega3) is K = L M: N for the
shear/stretch block, J for the coupling block, J m for bend/twist. In the paper's
units (Sec 2.2, dna_models.units: force C, length l = sqrt(I / rho)) the
dimensionless K* = S K S / C with S = diag(1, 1, 1, 1/l, 1/l, 1/l) (so the diagonal
of the bend block is the paper's D* = D rho / (I C)); Gamma0* = mean translation / L,
Omega0* = l mean angle / L; rho* = rho / rho_paper, I* = I / I_paper.
"""
from __future__ import annotations

import numpy as np

from dna_models.units import Units

from .constants import ANGSTROM, DEG, kT_J
from .continuum import to_radians
from .stiffness import stiffness


def segment_rod_material(mean, cov, temperature_K: float, n_eff=None, units: Units | None = None) -> dict:
    """K (6, 6) SI, K_star (6, 6), Gamma0_star (3,), Omega0_star (3,) of one segment
    ensemble (mean (6,), cov (6, 6) in A and deg)."""
    u = units or Units.paper()
    mean = np.asarray(mean, dtype=float)
    L_A = mean[2]
    M = stiffness(to_radians(np.asarray(cov, float)), 1.0, n_eff)    # kT / (A^a rad^b)
    kT = kT_J(temperature_K)
    # K = L M in SI: translations in m, angles in rad, L in m
    s = np.array([1 / ANGSTROM] * 3 + [1.0] * 3)                      # per A -> per m
    K = (L_A * ANGSTROM) * kT * M * s[:, None] * s[None, :]
    K_star = u.stiffness_to_rod(K)
    Gamma0 = mean[:3] / L_A
    Omega0 = mean[3:] * DEG / L_A * u.ell_A
    return {"K_SI": K, "K_star": K_star, "Gamma0_star": Gamma0, "Omega0_star": Omega0,
            "segment_length_A": L_A}
