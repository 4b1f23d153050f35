"""The slack tension of a box-held rod at a temperature: thermal bending stores contour, the
box keeps the projected length, so the rod stretches and pulls on the box.

Rod units throughout (dna_models/units.py converts). A straight uniform rod of rest length L
(Gamma0 = e3, bend stiffness B = D1 = D2, shear C1 = C2, stretch C3), held periodic with box
length X = L along the lab axis e. To second order in the fluctuations the projected length
per unit length is (docs/thermal.md, "Slack tension")

    X / L = <(1 + eps)(1 - |tau|^2 / 2) - tau . g>,

with tau the tilt of d3 off the axis, g the shear strain (Gamma1, Gamma2) seen in the lab and
eps = Gamma3 - 1. The transverse fields are sums of lab Fourier modes k_n = 2 pi n / L,
n = 1 .. N/2, four real amplitudes (t, g) each (two directions, two quadratures), with energy
(L/4) (B k^2 t^2 + C1 g^2) and stored contour t^2/4 + t g/2 per unit length; the n = 0 pair is
a uniform tilt t0 with shear g0 = -t0 (the box keeps the mean slope zero). The uniform stretch
is slaved: eps = (1 + c) / (1 - s) - 1 with s = sum t^2/4 and c = sum t g/2 (the n = 0 pair:
t0^2/2 and -t0^2), at energy C3 L eps^2 / 2, and the box pulls with

    F = <dE/dX> = <C3 eps / (1 - s)>

(the mean force of the constraint: the change of E per unit change of X along a uniform
stretch, which moves nothing else).

Mean field: the stretch energy replaced by F L (s + c) gives independent Gaussian modes with
the quadratic form [[B k^2 + F, F], [F, C1]] per amplitude pair, and F = C3 <s + c>(F) solved by
iteration (the docs' F = EA s(F), s(F) = (2 kT / L) sum 1 / (B k^2 + F), is its shear-free
limit). The exact value of this Gaussian-mode model (the stretch energy kept whole: the slack's
fluctuations are bounded by it) is the mean-field ensemble reweighted by
exp(-[C3 L eps^2 / 2 - F L (s + c)] / kT), by Monte Carlo.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class SlackTension:
    """The slack tension in rod force units: `mean_field` (the self-consistent Gaussian modes),
    `exact` (the model with the stretch energy kept whole, Monte Carlo) and its `error`, and
    the stored contour `slack` = <s + c> of the mean field."""
    mean_field: float
    exact: float
    error: float
    slack: float
    shear_free: float  # F = C3 s(F) without shear (the docs' first formula)


def _pair_covariances(k: np.ndarray, kT: float, L: float, B: float, C1: float, F: float) -> np.ndarray:
    """(n, 2, 2) covariance of (t, g) per real amplitude: energy (L/4) x.A x, A = [[Bk^2+F, F], [F, C1]]."""
    A = np.zeros((len(k), 2, 2))
    A[:, 0, 0] = B * k ** 2 + F
    A[:, 0, 1] = A[:, 1, 0] = F
    A[:, 1, 1] = C1
    return 2.0 * kT / L * np.linalg.inv(A)


def _mean_slack(k, kT, L, B, C1, F) -> float:
    cov = _pair_covariances(k, kT, L, B, C1, F)
    per_pair = cov[:, 0, 0] / 4 + cov[:, 0, 1] / 2          # <t^2/4 + t g/2>
    zero = -kT / (L * (C1 - F))                              # two n = 0 pairs: <-t0^2/2>, var kT/(L (C1 - F))
    return 4 * per_pair.sum() + zero


def slack_tension(L: float, N: int, kT: float, B: float, C1: float, C3: float,
                  samples: int = 100_000, seed: int = 1) -> SlackTension:
    """The tension of a box-held straight rod (rest length L, box L, N grid points, modes
    n = 1 .. N // 2) at kT; B, C1, C3 its bend, shear and stretch stiffness."""
    k = 2 * np.pi * np.arange(1, N // 2 + 1) / L
    F = 0.0
    for _ in range(500):
        F_new = C3 * _mean_slack(k, kT, L, B, C1, F)
        if abs(F_new - F) <= 1e-14 * max(1.0, abs(F)):
            break
        F = F_new
    shear_free = 0.0
    for _ in range(500):
        shear_free = C3 * 2 * kT / L * np.sum(1 / (B * k ** 2 + shear_free))
    # the exact model: the mean-field ensemble reweighted
    rng = np.random.default_rng(seed)
    cov = _pair_covariances(k, kT, L, B, C1, F)
    chol = np.linalg.cholesky(cov)
    s = np.zeros(samples)
    c = np.zeros(samples)
    for j in range(len(k)):
        z = rng.standard_normal((samples, 4, 2)) @ chol[j].T   # four (t, g) pairs
        s += (z[..., 0] ** 2).sum(1) / 4
        c += (z[..., 0] * z[..., 1]).sum(1) / 2
    t0 = rng.standard_normal((samples, 2)) * math.sqrt(kT / (L * (C1 - F)))
    s += (t0 ** 2).sum(1) / 2
    c -= (t0 ** 2).sum(1)
    eps = (1 + c) / (1 - s) - 1
    log_w = -(C3 * L * eps ** 2 / 2 - F * L * (s + c)) / kT
    w = np.exp(log_w - log_w.max())
    w /= w.sum()
    force = C3 * eps / (1 - s)
    exact = float(np.sum(w * force))
    ess = 1.0 / np.sum(w ** 2)
    error = float(math.sqrt(np.sum(w * (force - exact) ** 2) / ess))
    return SlackTension(mean_field=float(F), exact=exact, error=error, slack=float(F / C3),
                        shear_free=float(shear_free))


def box_for_tension(F: float, L: float, N: int, kT: float, B: float, C1: float, C3: float) -> float:
    """The box length X / L at which the box-held rod of `slack_tension` holds the tension F
    (rod force units), mean field: X / L = <(1 + eps)(1 - s) - c> = 1 + F / C3 - <s + c>(F)
    to second order, the stored contour <s + c> taken with the modes' covariance at F. At
    X = L it gives back the mean-field slack tension."""
    k = 2 * np.pi * np.arange(1, N // 2 + 1) / L
    return float(1.0 + F / C3 - _mean_slack(k, kT, L, B, C1, F))
