"""Base reference frames by least-squares fit of the standard base (Olson et
al. 2001; 3DNA tech-details sections 1-2).

The standard base's ring atoms S (n, 3), given in the standard frame, are
fitted onto the observed ring atoms E (..., n, 3) by the proper rotation R and
translation o minimising sum |E - (R S + o)|^2. R's columns are then the base's
x, y, z axes in the laboratory and o its origin.

Two solvers of the same problem (the minimiser is unique, so they agree to
round-off; tests check it):
* "horn" (default, as 3DNA): R from the unit quaternion that is the top
  eigenvector of Horn's 4x4 matrix built from the cross-covariance. The
  eigenvector comes from repeated squaring of the matrix shifted to be
  positive semi-definite: eight batched 4x4 products, no per-matrix LAPACK
  call, ~10x faster than a batched SVD on millions of bases. Convergence
  needs a gap between the two largest eigenvalues: they are s1+s2+s3 and
  s1-s2-s3 (singular values of the cross-covariance) for a proper fit, and
  the gap 2(s2+s3) is large for any base (a planar ring spreads in 2D).
* "svd" (Kabsch): reference implementation.
"""
from __future__ import annotations

import numpy as np

_SQUARINGS = 7   # contraction ratio <~ 0.6 for base rings -> 0.6^(2^7) ~ 1e-28


def _horn_entries(H):
    """Upper triangle of Horn's symmetric 4x4 matrix (3DNA tech-details M) from
    H[a][b] = sum_n s_a e_b, as a dict {(i, j): array}."""
    Sxx, Sxy, Sxz = H[0][0], H[0][1], H[0][2]
    Syx, Syy, Syz = H[1][0], H[1][1], H[1][2]
    Szx, Szy, Szz = H[2][0], H[2][1], H[2][2]
    return {(0, 0): Sxx + Syy + Szz, (1, 1): Sxx - Syy - Szz,
            (2, 2): -Sxx + Syy - Szz, (3, 3): -Sxx - Syy + Szz,
            (0, 1): Syz - Szy, (0, 2): Szx - Sxz, (0, 3): Sxy - Syx,
            (1, 2): Sxy + Syx, (1, 3): Szx + Sxz, (2, 3): Syz + Szy}


def _quaternion_matrix(q):
    q0, q1, q2, q3 = q
    R = np.empty(q0.shape + (3, 3))
    R[..., 0, 0] = q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3
    R[..., 0, 1] = 2 * (q1 * q2 - q0 * q3)
    R[..., 0, 2] = 2 * (q1 * q3 + q0 * q2)
    R[..., 1, 0] = 2 * (q2 * q1 + q0 * q3)
    R[..., 1, 1] = q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3
    R[..., 1, 2] = 2 * (q2 * q3 - q0 * q1)
    R[..., 2, 0] = 2 * (q3 * q1 - q0 * q2)
    R[..., 2, 1] = 2 * (q3 * q2 + q0 * q1)
    R[..., 2, 2] = q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3
    return R


def _sym(A, i, j):
    return A[(i, j)] if i <= j else A[(j, i)]


def _power(A, squarings):
    """A^(2^squarings), rescaled by its trace each time (A symmetric, dict form)."""
    for _ in range(squarings):
        inv = 1.0 / (A[(0, 0)] + A[(1, 1)] + A[(2, 2)] + A[(3, 3)])   # > 0: entries stay O(1)
        A = {k: v * inv for k, v in A.items()}
        A = {(i, j): sum(_sym(A, i, k) * _sym(A, k, j) for k in range(4)) for (i, j) in A}
    return A


def _rotation_horn(H):
    """H (..., 3, 3) -> R (..., 3, 3). Works on structure-of-arrays (each matrix
    entry one contiguous vector over all bases), so the squarings are ~100
    long vector operations instead of millions of tiny matrix products."""
    lead = H.shape[:-2]
    H = H.reshape(-1, 3, 3)
    Hs = [[np.ascontiguousarray(H[:, a, b]) for b in range(3)] for a in range(3)]
    N = _horn_entries(Hs)
    # With singular values s1 >= s2 >= s3 of H (proper case), N's eigenvalues are
    # s1+s2+s3 > s1-s2-s3 >= -s1+s2-s3 >= -s1-s2+s3. Any shift c > 0 makes the top
    # one strictly the largest in modulus; c ~ s2 gives the fastest contraction
    # ((s1-s3)/(s1+2 s2), 1/3 for a round planar ring). |H|_F/sqrt(2) is s2 for a
    # round ring and within a factor 2 of it for any base.
    c = np.sqrt(0.5 * sum(Hs[a][b] ** 2 for a in range(3) for b in range(3)))
    A0 = {k: (v + c if k[0] == k[1] else v) for k, v in N.items()}
    with np.errstate(divide="ignore", invalid="ignore"):  # degenerate input -> SVD below
        A = _power(A0, _SQUARINGS)
    # A ~ q q^T (times a positive number): its largest column is along q
    diag = np.stack([A[(i, i)] for i in range(4)])
    col = np.argmax(diag, axis=0)
    cols = np.stack([np.stack([_sym(A, i, j) for i in range(4)]) for j in range(4)])  # (j, i, ...)
    q = np.take_along_axis(cols, col[None, None], axis=0)[0]                          # (4, ...)
    with np.errstate(divide="ignore", invalid="ignore"):
        q = q / np.sqrt(np.sum(q * q, axis=0))
    # one power step with the unsquared matrix (removes rounding of the squarings)
    q = np.stack([sum(_sym(A0, i, j) * q[j] for j in range(4)) for i in range(4)])
    with np.errstate(divide="ignore", invalid="ignore"):
        q = q / np.sqrt(np.sum(q * q, axis=0))
    # verify: q must be an eigenvector of N; anything unconverged (never seen for
    # bases, possible for degenerate input) is redone by SVD
    Nq = np.stack([sum(_sym(N, i, j) * q[j] for j in range(4)) for i in range(4)])
    lam = np.sum(q * Nq, axis=0)
    resid = np.sqrt(np.sum((Nq - lam * q) ** 2, axis=0))
    R = _quaternion_matrix(q)
    bad = ~(resid <= 1e-10 * (c + 1e-300))
    if np.any(bad):
        R[bad] = _rotation_svd(H[bad])
    return R.reshape(lead + (3, 3))


def _rotation_svd(H):
    U, _, Vt = np.linalg.svd(H)
    V = np.swapaxes(Vt, -1, -2)
    # proper rotation: flip the weakest direction if the best orthogonal map is a reflection
    d = np.sign(np.linalg.det(V @ np.swapaxes(U, -1, -2)))
    d = np.where(d == 0, 1.0, d)
    V[..., :, 2] *= d[..., None]
    return V @ np.swapaxes(U, -1, -2)


def fit_frames(standard, observed, method="horn"):
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
    H = np.swapaxes(Sc, -1, -2) @ Ec               # cross-covariance S^T E
    R = _rotation_horn(H) if method == "horn" else _rotation_svd(H)
    o = e_ave - np.einsum("...ij,...j->...i", R, s_ave)
    # residuals from the fitted coordinates themselves (the shortcut
    # |Sc|^2 + |Ec|^2 - 2 tr(R H^T) cancels to ~1e-8 A for exact fits)
    sq = 0.0
    for k in range(3):
        fit_k = R[..., None, k, 0] * Sc[..., 0] + R[..., None, k, 1] * Sc[..., 1] + R[..., None, k, 2] * Sc[..., 2]
        sq = sq + (Ec[..., k] - fit_k) ** 2
    rmsd = np.sqrt(np.mean(sq, axis=-1))
    return R, o, rmsd
