"""Helical axis of a periodic duplex from base-pair origins: a one-turn window.

Base-pair origins of real DNA sit off the helical axis by a small radius (the
3DNA x-displacement) that turns with the helix. Averaging the origins over
exactly one helical turn cancels that offset and leaves the axis. The window
has 2m+1 full weights and two fractional end weights f, with f chosen so that
the window's response to a helix of the mean twist theta is exactly zero:

    1 + 2 sum_{j=1..m} cos(j theta) + 2 f cos((m+1) theta) = 0,

i.e. a uniform-twist offset helix is removed exactly ("twist-weighted").
The window wraps around the periodic ends: origin i+n is origin i shifted by
the period vector P. For the rod, whose base-pair origins lie on the
centerline, the same window only smooths: a displacement of wavenumber k is
scaled by the window's response H(k) (0.993 for 158 bp, 15 turns, k = 2 pi / L),
which `window_response` reports.
"""
from __future__ import annotations

import numpy as np


def mean_twist(R: np.ndarray) -> float:
    """Mean twist per step [rad] of a closed ring of frames R (n, 3, 3), columns x, y, z.

    The twist of step i -> i+1 is the rotation angle about z of R_i^T R_{i+1}
    (exact for a pure twist; bend changes it only at second order). The ring
    closes (step n-1 -> 0), as for a ligated periodic duplex.
    """
    Q = np.einsum("iab,iac->ibc", R, np.roll(R, -1, axis=0))
    twist = np.arctan2(Q[:, 1, 0] - Q[:, 0, 1], Q[:, 0, 0] + Q[:, 1, 1])
    return float(np.mean(twist))


def one_turn_weights(theta: float, n: int) -> np.ndarray:
    """Window weights w_j, j = -(m+1)..(m+1), normalised to sum 1 (see module doc).

    theta: mean twist per base pair [rad]. When the whole duplex holds less than
    one turn (untwisted rod) there is no helix to cancel: the window is [1].
    """
    theta = abs(theta)
    if theta * n < 2 * np.pi or theta < 1e-12:
        return np.array([1.0])
    n_turn = 2 * np.pi / theta
    m = int(np.floor((n_turn - 1) / 2))
    dirichlet = 1 + 2 * sum(np.cos(j * theta) for j in range(1, m + 1))
    c = np.cos((m + 1) * theta)
    f = -dirichlet / (2 * c) if abs(c) > 1e-6 else np.nan
    if not np.isfinite(f) or f < 0 or f > 1:
        f = (n_turn - 1) / 2 - m  # fall back to the plain one-turn length
    w = np.ones(2 * m + 3)
    w[0] = w[-1] = f
    return w / w.sum()


def window_response(w: np.ndarray, k_per_bp: float) -> float:
    """Response H(k) = sum_j w_j cos(j k) of a symmetric window to wavenumber k [rad/bp]."""
    h = (len(w) - 1) // 2
    j = np.arange(-h, h + 1)
    return float(np.sum(w * np.cos(j * k_per_bp)))


def helical_axis(origins: np.ndarray, R: np.ndarray, period: np.ndarray,
                 weights: np.ndarray | None = None):
    """Axis points (n, 3) at each base pair of one frame of a periodic duplex.

    origins: (n, 3) base-pair origins, continuous along the strand (consecutive
    origins are nearest images); R: (n, 3, 3) base-pair frames; period: (3,)
    vector P with origin_{i+n} = origin_i + P. Returns (axis, weights).
    """
    n = len(origins)
    if weights is None:
        weights = one_turn_weights(mean_twist(R), n)
    h = (len(weights) - 1) // 2
    axis = np.zeros_like(origins, dtype=float)
    idx = np.arange(n)
    for j, wj in zip(range(-h, h + 1), weights):
        k = idx + j
        axis += wj * (origins[k % n] + np.floor_divide(k, n)[:, None] * period[None, :])
    return axis, weights
