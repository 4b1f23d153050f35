"""Composing the rod's strains along s: the rigid motion of a stretch of rod.

The rod between grid points is the trigonometric interpolant of the grid
strains x = (Gamma, Omega) (the field the spectral operator sees). Its motion
over a stretch is the ordered product of the SE(3) exponentials of the
interpolant at the midpoints of `refine` sub-cells per grid cell (midpoint
rule on the Lie group: error O((ds / refine)^2) times the strain variation).
"""
from __future__ import annotations

import numpy as np

from mdbridge.geometry.se3 import step_exp
from mdbridge.rod.frames import trig_interpolate


def chain_product(A):
    """Ordered product A[..., 0, :, :] @ A[..., 1, :, :] @ ... of (..., M, 4, 4), pairwise."""
    while A.shape[-3] > 1:
        if A.shape[-3] % 2:
            A = np.concatenate([A, np.broadcast_to(np.eye(4), A.shape[:-3] + (1, 4, 4))], axis=-3)
        A = A[..., 0::2, :, :] @ A[..., 1::2, :, :]
    return A[..., 0, :, :]


def cell_matrix(N, L, refine):
    """(M, N): grid values -> the trigonometric interpolant at the refine*N cell midpoints.
    The interpolant of grid value j is that of value 0 moved by j grid cells (refine cells),
    so column j is column 0 rolled by refine j: O(M N) instead of a dense interpolation."""
    M = refine * N
    e0 = np.zeros((N, 1))
    e0[0] = 1.0
    b = trig_interpolate(e0, 0.0, L / N, (np.arange(M) + 0.5) * L / M)[:, 0]
    return np.stack([np.roll(b, refine * j) for j in range(N)], axis=1)


def compose_cells(xm, h):
    """Product of the SE(3) exponentials of the cell strains xm (..., M, 6): (R (..., 3, 3), d (..., 3))."""
    R, d = step_exp(xm[..., 3:] * h, xm[..., :3] * h)
    T = np.zeros(xm.shape[:-1] + (4, 4))
    T[..., :3, :3], T[..., :3, 3], T[..., 3, 3] = R, d, 1.0
    P = chain_product(T)
    return P[..., :3, :3], P[..., :3, 3]


def magnus_holonomy(x, L, max_turn=0.05):
    """The holonomy (R (3, 3), r (3,)) of the grid strains x (N, 6) = (Gamma, Omega) as rodsim's
    sweep composes it (rodcore/src/reconstruction.cpp: per grid interval m substeps, m = ceil(h
    max|Omega| / max_turn) <= 64, each the 4th-order Magnus step on the trigonometric interpolant
    at its two Gauss points; max_turn 0.05 is the output's sweep): a ring closed by it is closed
    in the solver's own frames, to round-off, where the midpoint cells above leave O((h /
    refine)^2)."""
    x = np.asarray(x, float)
    N = x.shape[0]
    h = L / N
    m = int(np.clip(np.ceil(min(h * np.max(np.linalg.norm(x[:, 3:], axis=1)) / max_turn, 64.0)), 1, 64))
    c = np.fft.rfft(x, axis=0) / N
    k = 2.0 * np.pi * np.arange(c.shape[0]) / L
    if N % 2 == 0:
        c[-1] = c[-1].real                          # the Nyquist mode as the real cosine
    hs = h / m
    gauss = (0.5 - np.sqrt(3.0) / 6.0, 0.5 + np.sqrt(3.0) / 6.0)
    at = np.empty((m, 2, N, 6))
    for sub in range(m):
        for a in range(2):
            ph = np.exp(1j * k * (sub + gauss[a]) * hs)
            if N % 2 == 0:
                ph[-1] = np.cos(k[-1] * (sub + gauss[a]) * hs)
            at[sub, a] = np.fft.irfft(c * ph[:, None], n=N, axis=0) * N
    x1, x2 = at[:, 0], at[:, 1]                     # (m, N, 6) in (Gamma, Omega)
    k3 = np.sqrt(3.0) / 12.0 * hs * hs
    phi = 0.5 * hs * (x1[..., 3:] + x2[..., 3:]) + k3 * np.cross(x1[..., 3:], x2[..., 3:])
    u = (0.5 * hs * (x1[..., :3] + x2[..., :3])
         + k3 * (np.cross(x1[..., 3:], x2[..., :3]) - np.cross(x2[..., 3:], x1[..., :3])))
    R, d = step_exp(phi, u)
    T = np.zeros((m, N, 4, 4))
    T[..., :3, :3], T[..., :3, 3], T[..., 3, 3] = R, d, 1.0
    P = chain_product(np.swapaxes(T, 0, 1).reshape(N * m, 4, 4))   # interval by interval, substeps in order
    return P[:3, :3], P[:3, 3]


def compose_stretches(xm, h, per):
    """Motions of consecutive stretches of `per` cells: (R (n, 3, 3), d (n, 3)) from
    cell strains xm (n * per, 6) of length h each."""
    M = xm.shape[-2]
    R, d = step_exp(xm[..., 3:] * h, xm[..., :3] * h)
    T = np.zeros(xm.shape[:-1] + (4, 4))
    T[..., :3, :3], T[..., :3, 3], T[..., 3, 3] = R, d, 1.0
    T = T.reshape(xm.shape[:-2] + (M // per, per, 4, 4))
    P = chain_product(T)
    return P[..., :3, :3], P[..., :3, 3]
