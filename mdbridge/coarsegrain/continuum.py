"""Physical constants of the continuum rod from the stiffness of m-step segments.

An m-step segment of contour length L (the sum of its steps' mean rises: the rod's
arclength; a bent segment's own rise, the chord along its mid-step z axis, is shorter
by O(bend^2)) behaves, in the continuum limit, as a uniform rod piece with
energy E = (L / 2) (x - x0)^T A (x - x0), x = (segment parameters) / L with angles
in radians. With the segment's stiffness M = kT <dq dq^T>^-1 (kT/A^2, kT/(A rad),
kT/rad^2) this gives A = L M. Each constant below uses the marginal covariance of
the parameters it involves (the other four are free, as in a force or torque
measurement), inverted with the finite-sample bias correction
(mdbridge.coarsegrain.stiffness):

* bend persistence length l_b = 2 L / (var tilt + var roll) [rad^2]: the decay
  length of the tangent correlation, <t(0).t(L)> = 1 - (var tilt + var roll) / 2
  = exp(-L / l_b) for small bends; for an anisotropic rod whose twist mixes the two
  bends this is the harmonic mean of A1 / kT and A2 / kT.
  (l_b uses variances directly; the O(1 / N_eff) bias of their inverse is below the
  bootstrap error.)
* bend_persistence_length_tangent = -L / ln <cos Gamma>, Gamma the segment's bend
  angle (estimator.py): the worm-like chain's exact tangent correlation, which also
  counts the static (intrinsic) bends. On a worm-like chain of independent steps both
  forms return l_b at every m up to 20 within 1.5 % (test_coarsegrain_physics.py).
* Twist and stretch of long segments are not pure: the CEHS twist of a bent segment
  and its chord length pick up bend contributions of second order, so the apparent
  torsional and stretch moduli fall with m even for uncoupled steps (measured on the
  same chain: -10 % and -40 % at m = 20); they are physical for the chord-and-CEHS
  definitions, and the continuum limit is read where the curves level off.
* twist: C = L kT / var twist (pN nm^2), torsional persistence l_t = C / kT (nm).
* stretch modulus and twist-stretch coupling from the 2 x 2 (rise, twist) block:
  kT [[var rise, c], [c, var twist]]^-1 = [[S, g], [g, C_s]] / L, so S (pN) and
  g (pN nm) with E / L = S u^2 / 2 + g u w + C_s w^2 / 2 for strain u = dL / L and
  twist density w = dTheta / L (right-handed twist positive). Sign convention:
  g < 0 means the molecule overwinds when stretched (at fixed zero torque,
  dw / du = -g / C_s > 0), as measured for DNA (Gore et al. 2006 Nature 442:836;
  Marin-Gonzalez et al. 2017 PNAS 114:7049).
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


def physical_constants(mean, cov, temperature_K: float, n_eff=None, length_A=None) -> dict:
    """Constants of one segment ensemble: mean (..., 6) and covariance (..., 6, 6) of
    the segment parameters in (A, deg); n_eff effective frames for the bias
    correction (None: none); length_A the segment's contour length (None: its mean
    rise). Returns {name: array (...)} in nm, pN, pN nm^2, pN nm."""
    kT = kT_pN_nm(temperature_K)                   # pN nm
    c = to_radians(np.asarray(cov, dtype=float))
    L_nm = (np.asarray(mean, dtype=float)[..., RISE] if length_A is None else np.asarray(length_A)) / 10.0
    var_bend = c[..., TILT, TILT] + c[..., ROLL, ROLL]
    l_b = 2.0 * L_nm / var_bend
    C = L_nm * kT / c[..., TWIST, TWIST]
    f1 = 1.0 if n_eff is None else bias_factor(n_eff, 1)
    f2 = 1.0 if n_eff is None else bias_factor(n_eff, 2)
    C = C * f1
    nm = np.array([0.1, 1.0])                                     # rise in nm, twist in rad
    rt = c[..., [RISE, TWIST], :][..., :, [RISE, TWIST]] * nm[:, None] * nm[None, :]
    M = kT * np.linalg.inv(rt) * np.asarray(f2)[..., None, None]
    return {"bend_persistence_length": l_b,
            "torsional_persistence_length": C / kT,
            "torsional_modulus": C,
            "stretch_modulus": L_nm * M[..., 0, 0],
            "twist_stretch_coupling": L_nm * M[..., 0, 1],
            "twist_stiffness_at_fixed_extension": L_nm * M[..., 1, 1],
            "segment_length": np.broadcast_to(L_nm, np.shape(l_b)).copy()}


UNITS = {"bend_persistence_length": "nm", "bend_persistence_length_tangent": "nm", "torsional_persistence_length": "nm",
         "torsional_modulus": "pN nm^2", "stretch_modulus": "pN",
         "twist_stretch_coupling": "pN nm", "twist_stiffness_at_fixed_extension": "pN nm^2",
         "segment_length": "nm"}
