"""Thermal motion of the fundamental bend mode and when a kicked frequency is measurable
(docs/analysis.md, "Small amplitudes").

Thermal amplitude (equipartition). For u_in(s) = q_c cos(ks) + q_s sin(ks) on a closed rod
of length L under axial force T, the bend + tension energy is
(1/2)(D k^4 + T k^2)(L/2)(q_c^2 + q_s^2), so each quadrature holds kT/2 and the complex mode
amplitude c = q_c - i q_s (wavespeed.mode_amplitude) has
    <|c|^2> = 4 kT / ((D k^4 + T k^2) L).
For the paper's D (persistence length 66 nm at 300 K), 158 bp x 3.38 A and T = 0 this is
24 A rms -- as large as the response to A_v = 0.1 A/ps (A_v / omega ~ 15-25 A).

The oscillator of the synthetic study (bench/thermal_mode_study.py, docs/analysis.md): each
spatial quadrature of the mode is an underdamped Langevin oscillator at omega with quality
factor Q (its coupling to the other modes), at the thermal rms above, sampled exactly
(discrete-time transition of the linear SDE).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.linalg import expm

from dna_models.units import BOLTZMANN as KB


def thermal_mode_rms_A(length_A: float, D_J_m: float, T_K: float = 300.0, tension_pN: float = 0.0) -> float:
    """rms |c| [A] of the fundamental in one transverse direction (module doc)."""
    L = length_A * 1e-10
    k = 2 * math.pi / L
    return math.sqrt(4 * KB * T_K / ((D_J_m * k ** 4 + tension_pN * 1e-12 * k ** 2) * L)) * 1e10


def _oscillator(rng, n_real, n, dt, omega, Q, rms_quadrature):
    """Stationary underdamped Langevin oscillator x'' + g x' + w^2 x = noise, exact in time."""
    g = omega / Q
    A = np.array([[0.0, 1.0], [-omega ** 2, -g]])
    F = expm(A * dt)
    S = np.diag([rms_quadrature ** 2, (omega * rms_quadrature) ** 2])  # stationary covariance
    Qd = S - F @ S @ F.T
    Lq = np.linalg.cholesky(Qd + 1e-300 * np.eye(2))
    Ls = np.linalg.cholesky(S)
    x = np.empty((n_real, n))
    st = rng.standard_normal((n_real, 2)) @ Ls.T
    for i in range(n):
        x[:, i] = st[:, 0]
        st = st @ F.T + rng.standard_normal((n_real, 2)) @ Lq.T
    return x
