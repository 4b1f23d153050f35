"""Physical constants of the continuum rod from the fluctuations of m-step segments.

A segment of contour length L (the sum of its steps' mean rises: the rod's arclength)
behaves, in the continuum limit, as a uniform rod piece with energy
E = (L / 2) (x - x0)^T A (x - x0), x = (segment parameters) / L with angles in radians,
so that A = L kT <dq dq^T>^-1. Each constant uses the marginal covariance of the
parameters it involves (the other parameters free, as in a force or torque
measurement), inverted with the finite-sample bias correction (stiffness.py):

* bend persistence length l_b = 2 L / (var tilt + var roll) [rad^2] of the segment's
  own (composed) tilt and roll: the decay length of the tangent correlation,
  <t(0).t(L)> = 1 - (var tilt + var roll) / 2 = exp(-L / l_b) for small bends; for an
  anisotropic rod whose twist mixes the two bends this is the harmonic mean of A1 / kT
  and A2 / kT. (It uses variances directly; their inverse's O(1 / N_eff) bias is below
  the bootstrap error.) bend_persistence_length_tangent = -L / ln <cos Gamma>, Gamma
  the segment's bend angle (estimator.py), also counts static (intrinsic) bends. On a
  worm-like chain of independent steps both return l_b at every m up to 20 within
  1.5 % (test_coarsegrain_physics.py).
* twist and stretch (`contour_constants`), from the segment's summed rise (its contour
  length) and summed twist (its total twist Tw), the rod's Gamma3 and Omega3 integrated
  over it: C = L kT / var Tw (pN nm^2), torsional persistence l_t = C / kT (nm); and
  from the 2 x 2 (rise, twist) block, kT [[var L, c], [c, var Tw]]^-1 L = [[S, g],
  [g, C_s]]: the stretch modulus S (pN), the twist-stretch coupling g (pN nm) and the
  twist stiffness at fixed extension C_s, for E / L = S u^2 / 2 + g u w + C_s w^2 / 2
  with strain u = dL / L and twist density w (right-handed twist positive).
  Sign convention: g < 0 means the molecule overwinds when stretched (at fixed zero
  torque, dw / du = -g / C_s > 0), as measured for DNA (Gore et al. 2006 Nature
  442:836; Marin-Gonzalez et al. 2017 PNAS 114:7049).
* the same from the segment's own (composed, CEHS) rise and twist, named *_segment:
  equal at m = 1, but a bent segment's chord and CEHS twist pick up second-order bend
  contributions, so these fall with m even for uncoupled steps (on the test chain:
  torsional -10 % and stretch -40 % at m = 20); reported for comparison with tools
  that use the end-to-end chord.
"""
from __future__ import annotations

import numpy as np

from .constants import DEG, kT_pN_nm
from .stiffness import bias_factor

RISE, TILT, ROLL, TWIST = 2, 3, 4, 5


def to_radians(cov_deg: np.ndarray) -> np.ndarray:
    """Covariance in (A, deg) -> (A, rad)."""
    s = np.array([1.0, 1.0, 1.0, DEG, DEG, DEG])
    return cov_deg * s[:, None] * s[None, :]


def _stretch_twist(L_nm, block_deg, kT, n_eff, suffix=""):
    """Torsional, stretch and coupling constants from the (rise [A], twist [deg])
    covariance block (..., 2, 2) of segments of length L."""
    nm = np.array([0.1, DEG])                                     # rise in nm, twist in rad
    rt = np.asarray(block_deg, dtype=float) * nm[:, None] * nm[None, :]
    f1 = 1.0 if n_eff is None else bias_factor(n_eff, 1)
    f2 = 1.0 if n_eff is None else bias_factor(n_eff, 2)
    C = L_nm * kT / rt[..., 1, 1] * f1
    M = kT * np.linalg.inv(rt) * np.asarray(f2)[..., None, None]
    return {"torsional_persistence_length" + suffix: C / kT, "torsional_modulus" + suffix: C,
            "stretch_modulus" + suffix: L_nm * M[..., 0, 0],
            "twist_stretch_coupling" + suffix: L_nm * M[..., 0, 1],
            "twist_stiffness_at_fixed_extension" + suffix: L_nm * M[..., 1, 1]}


def physical_constants(mean, cov, temperature_K: float, n_eff=None, length_A=None) -> dict:
    """Constants of one segment ensemble: mean (..., 6) and covariance (..., 6, 6) of
    the segment parameters in (A, deg); n_eff effective frames for the bias
    correction (None: none); length_A the segment's contour length (None: its mean
    rise). Bend from the segment's tilt and roll; twist and stretch from its own
    (CEHS) rise and twist, named *_segment. Returns {name: array (...)} in nm, pN,
    pN nm^2, pN nm."""
    kT = kT_pN_nm(temperature_K)                   # pN nm
    c = to_radians(np.asarray(cov, dtype=float))
    L_nm = (np.asarray(mean, dtype=float)[..., RISE] if length_A is None else np.asarray(length_A)) / 10.0
    l_b = 2.0 * L_nm / (c[..., TILT, TILT] + c[..., ROLL, ROLL])
    block = np.asarray(cov, dtype=float)[..., [RISE, TWIST], :][..., :, [RISE, TWIST]]
    out = {"bend_persistence_length": l_b}
    out.update(_stretch_twist(L_nm, block, kT, n_eff, "_segment"))
    out["segment_length"] = np.broadcast_to(L_nm, np.shape(l_b)).copy()
    return out


def contour_constants(mean2, cov2, temperature_K: float, n_eff=None) -> dict:
    """Twist and stretch constants from the sums over a segment's steps of rise and
    twist (mean (..., 2), covariance (..., 2, 2) in A and deg): the segment's contour
    length and its total twist Tw. These are the rod's Gamma3 and Omega3 integrated
    over the segment, free of the bend contributions that the segment's own chord and
    CEHS twist pick up, so for uncorrelated steps they are the same at every m."""
    kT = kT_pN_nm(temperature_K)
    L_nm = np.asarray(mean2, dtype=float)[..., 0] / 10.0
    return _stretch_twist(L_nm, cov2, kT, n_eff)


UNITS = {"bend_persistence_length": "nm", "bend_persistence_length_tangent": "nm",
         "segment_length": "nm"}
for _sfx in ("", "_segment"):
    UNITS.update({"torsional_persistence_length" + _sfx: "nm", "torsional_modulus" + _sfx: "pN nm^2",
                  "stretch_modulus" + _sfx: "pN", "twist_stretch_coupling" + _sfx: "pN nm",
                  "twist_stiffness_at_fixed_extension" + _sfx: "pN nm^2"})
