"""Rest shape of a pre-stressed duplex (the box constraint).

A periodic ligated duplex is held at the box length and at a fixed linking number,
so its mean step parameters are those of a stressed state: with a mean tension F
along the helix axis and a mean torque tau about it, each step carries the
generalised force f = (0, 0, F, 0, 0, tau) conjugate to (shift, slide, rise, tilt,
roll, twist) (the step's z axis is taken as the helix axis; for B-DNA they differ by
a few degrees). For a harmonic step, E = 1/2 (q - q0)^T K (q - q0) - f.q, so the
mean is <q> = q0 + K^-1 f = q0 + <dq dq^T> f / kT and the rest shape is

    q0 = <q> - <dq dq^T> f / kT

(covariance in A and deg; F in pN and tau in pN nm converted to kT/A and kT/deg).
It needs no stiffness inversion. F and tau come from a measurement (the comparison's
measured mean stress, or the axis-only pressure-coupled MD); without them the mean
is reported uncorrected and labelled as the pre-stressed shape. A positive F means
the box stretches the duplex; a positive tau overwinds it.
"""
from __future__ import annotations

import numpy as np

from .constants import DEG, kT_pN_nm


def generalised_force(tension_pN: float, torque_pN_nm: float, temperature_K: float) -> np.ndarray:
    """f / kT (6,) in 1/A and 1/deg."""
    kT = kT_pN_nm(temperature_K)
    f = np.zeros(6)
    f[2] = tension_pN * 0.1 / kT           # pN * A = 0.1 pN nm
    f[5] = torque_pN_nm * DEG / kT          # pN nm per rad -> per deg
    return f


def rest_shape(mean, cov, tension_pN: float, torque_pN_nm: float, temperature_K: float):
    """q0 (..., 6) = mean - cov f / kT."""
    f = generalised_force(tension_pN, torque_pN_nm, temperature_K)
    return np.asarray(mean) - np.einsum("...ij,j->...i", np.asarray(cov), f)
