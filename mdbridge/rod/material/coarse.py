"""Coarse segments: one grid point per m base pairs, the material composed from the steps it replaces
(`dnarod dna-rod --bp-per-point m`; docs/dna-rod.md, "Coarse segments").

Shape. Segment k is the rigid motion G_k = g_{km} g_{km+1} ... g_{km+m-1} of its m steps (their rest
motions, steps_to_rod.strains_from_steps), and its constant strains over H = m h are the SE(3)
logarithm of G_k over H, on the principal branch: ten steps of ~34 deg make ~343 deg, which the
logarithm reads as -17 deg. The rod's frame at every segment boundary is then exactly the base pair's
frame there, and its intrinsic twist differs from the DNA's by whole turns per segment, recorded as
`turns` (the DNA's Tw and Lk are the rod's plus sum(turns)). The twist the rod fluctuates about, and
every energy, is unchanged: a rotation does not know its turns.

Stiffness: series compliance, transported. A step's strain deviation e_i (rod units) moves it by
delta_i = J_i e_i (J_i = d log(g0_i^-1 g_i) / d e_i, the right-trivialised perturbation, by central
differences of the exact map), with covariance kT K_i^-1 / h. Composed, G = G0 exp(delta) with

    delta = sum_i Ad(Q_i)^-1 delta_i,   Q_i = g0_{i+1} ... g0_{km+m-1}  (the rest motion after step i),

so Cov(delta) = sum_i Ad(Q_i)^-1 J_i K_i^-1 J_i^T Ad(Q_i)^-T / h (kT = 1): the adjoint turns each step's
compliance by the intrinsic twist that follows it (which averages the bend anisotropy over the helical
turn) and adds the lever-arm terms of bend into shear. The segment's stiffness per length makes a
constant strain deviation over H have that covariance: K_seg^-1 / H = J_seg^-1 Cov(delta) J_seg^-T.
This is exact for the linearised chain (Gaussian steps); the persistence lengths of bend and twist of
the coarse chain equal the base-pair chain's to second order in a segment's fluctuation
(tests/python/test_material_coarse.py).

Mass and inertia: summed over the segment (rho and I per length averaged), I turned into the segment
frame; the parallel-axis term of the base pairs' offsets along the axis is left out (it matters to the
inertial rod's bending frequencies near the grid scale, not to the overdamped rod).
"""
from __future__ import annotations

import numpy as np

from dna_models.errors import InputError
from mdbridge.geometry.se3 import skew, step_exp, step_log

from .steps_to_rod import RodMaterial


def _motions(Gamma, Omega, h):
    """Rest rigid motions (R (n, 3, 3), d (n, 3)) of constant-strain pieces of length h."""
    return step_exp(np.asarray(Omega, float) * h, np.asarray(Gamma, float) * h)


def _adjoint(R, d):
    """Ad of g = (R, d) on (translation, rotation) twists, in the strain order (Gamma, Omega):
    [[R, [d]x R], [0, R]]."""
    A = np.zeros(R.shape[:-2] + (6, 6))
    A[..., :3, :3] = R
    A[..., :3, 3:] = skew(d) @ R
    A[..., 3:, 3:] = R
    return A


def _log_twist(R, d):
    """(Gamma, Omega) h of the motion (R, d): the SE(3) logarithm in the strain order."""
    v, w = step_log(R, d)
    return np.concatenate([w, v], axis=-1)


def perturbation_jacobian(Gamma0, Omega0, h, eps=1e-6):
    """J (..., 6, 6) = d log(g0^-1 g(e)) / d e at e = 0, g(e) the constant-strain piece of length h with
    strains (Gamma0, Omega0) + e; (translation, rotation) rows in the strain order."""
    x0 = np.concatenate([np.asarray(Gamma0, float), np.asarray(Omega0, float)], axis=-1)
    R0, d0 = _motions(x0[..., :3], x0[..., 3:], h)
    R0T = np.swapaxes(R0, -1, -2)
    J = np.empty(x0.shape[:-1] + (6, 6))
    for k in range(6):
        cols = []
        for sgn in (1.0, -1.0):
            x = x0.copy()
            x[..., k] += sgn * eps
            R, d = _motions(x[..., :3], x[..., 3:], h)
            cols.append(_log_twist(R0T @ R, np.einsum("...ji,...j->...i", R0, d - d0)))
        J[..., :, k] = (cols[0] - cols[1]) / (2 * eps)
    return J


def coarse_material(rm: RodMaterial, bp_per_point: int) -> tuple[RodMaterial, np.ndarray]:
    """(the RodMaterial of n_bp / m segments of m steps each, turns (n_seg,): the whole turns each
    segment's principal logarithm drops). Its per-step arrays have one row per segment, h = m h_bp,
    and its `sequence` one letter per segment (the segment's first base pair), so that n_bp counts
    the segments as grid_material expects; the DNA's sequence is the caller's."""
    m = int(bp_per_point)
    n = rm.K.shape[0]
    if m < 1 or n % m:
        raise InputError(f"--bp-per-point {m}: must divide the number of steps {n} (n_bp = {rm.n_bp})")
    if m == 1:
        return rm, np.zeros(n)
    h, H, n_seg = rm.h, m * rm.h, n // m
    R, d = _motions(rm.Gamma0, rm.Omega0, h)                      # (n, 3, 3), (n, 3)
    J = perturbation_jacobian(rm.Gamma0, rm.Omega0, h)            # (n, 6, 6)
    cov = J @ np.linalg.inv(rm.K) @ np.swapaxes(J, -1, -2) / h    # Cov(delta_i), kT = 1
    G0 = np.empty((n_seg, 6))
    K = np.empty((n_seg, 6, 6))
    turns = np.empty(n_seg)
    rho = np.empty(n_seg)
    I = np.empty((n_seg, 3, 3))
    for k in range(n_seg):
        steps = range(k * m, k * m + m)
        # Q_i: the rest motion after step i to the segment's end, built backwards
        QR, Qd = np.eye(3), np.zeros(3)
        C = np.zeros((6, 6))
        for i in reversed(steps):
            Ainv = _adjoint(QR.T, -QR.T @ Qd)                     # Ad(Q_i)^-1 = Ad(Q_i^-1)
            C += Ainv @ cov[i] @ Ainv.T
            QR, Qd = R[i] @ QR, R[i] @ Qd + d[i]                  # Q_{i-1} = g0_i Q_i
        x = _log_twist(QR, Qd) / H                                # QR, Qd: the whole segment G0
        G0[k] = x
        Jseg = perturbation_jacobian(x[:3], x[3:], H)
        Jinv = np.linalg.inv(Jseg)
        Ks = np.linalg.inv(H * Jinv @ C @ Jinv.T)
        K[k] = 0.5 * (Ks + Ks.T)
        # whole turns dropped: the steps' summed twist (rotation about d3) against the principal one
        turns[k] = np.round((float(np.sum(rm.Omega0[list(steps), 2])) * h - x[5] * H) / (2 * np.pi))
        # mass and inertia per length: the mean over the base pairs, I in the segment's frame
        # (base pair i's frame is the product of the rest rotations before it)
        Rb = np.eye(3)
        Is = np.zeros((3, 3))
        for i in steps:
            Is += Rb @ rm.I[i] @ Rb.T
            Rb = Rb @ R[i]
        I[k] = Is / m
        rho[k] = float(np.mean(rm.rho[list(steps)]))
    return RodMaterial(sequence=rm.sequence[::m], closed=rm.closed, h=H, h_A=m * rm.h_A, Gamma0=G0[:, :3],
                       Omega0=G0[:, 3:], K=K, rho=rho, I=I, source=f"{rm.source}, {m} bp per point"), turns
