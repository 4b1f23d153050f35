"""Base reference frames by least-squares fit of the standard base (Olson et
al. 2001; 3DNA tech-details section 1-2).

The standard base's ring atoms S (n, 3), given in the standard frame, are
fitted onto the observed ring atoms E (..., n, 3) by the proper rotation R and
translation o minimising sum |E - (R S + o)|^2. R's columns are then the base's
x, y, z axes in the laboratory and o its origin. 3DNA solves the same problem
with Horn's quaternion method; the minimiser is unique, so the Kabsch/SVD
solution used here is the same frame (to round-off).
"""
from __future__ import annotations

import numpy as np


def fit_frames(standard, observed):
    """Least-squares rigid fit of `standard` (n, 3) (or (..., n, 3), broadcast)
    onto `observed` (..., n, 3).

    Returns (R (..., 3, 3), o (..., 3), rmsd (...)) with observed ~ R S + o.
    """
    S = np.asarray(standard, dtype=float)
    E = np.asarray(observed, dtype=float)
    s_ave = S.mean(axis=-2)
    e_ave = E.mean(axis=-2)
    Sc = S - s_ave[..., None, :]
    Ec = E - e_ave[..., None, :]
    H = np.einsum("...ni,...nj->...ij", Sc, Ec)       # cross-covariance S^T E
    U, _, Vt = np.linalg.svd(H)
    V = np.swapaxes(Vt, -1, -2)
    # proper rotation: flip the weakest direction if the best orthogonal map is a reflection
    d = np.sign(np.linalg.det(V @ np.swapaxes(U, -1, -2)))
    d = np.where(d == 0, 1.0, d)
    V[..., :, 2] *= d[..., None]
    R = V @ np.swapaxes(U, -1, -2)
    o = e_ave - np.einsum("...ij,...j->...i", R, s_ave)
    fitted = np.einsum("...ij,...nj->...ni", R, S) + o[..., None, :]
    rmsd = np.sqrt(np.mean(np.sum((E - fitted) ** 2, axis=-1), axis=-1))
    return R, o, rmsd
