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
