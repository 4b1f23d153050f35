"""Optimal superposition (Kabsch) of one curve onto another and the RMSD after it."""
from __future__ import annotations

import numpy as np


def kabsch_rmsd(P: np.ndarray, Q: np.ndarray):
    """RMSD [same units] of points P (n, 3) optimally rotated and translated onto Q (n, 3).

    Returns (rmsd, R, t) with Q ~ P @ R.T + t. The determinant correction keeps R a proper
    rotation (no reflection).
    """
    P, Q = np.asarray(P, float), np.asarray(Q, float)
    pc, qc = P.mean(axis=0), Q.mean(axis=0)
    H = (P - pc).T @ (Q - qc)
    U, _, Vt = np.linalg.svd(H)
    d = np.sign(np.linalg.det(Vt.T @ U.T))
    R = Vt.T @ np.diag([1.0, 1.0, d]) @ U.T
    t = qc - pc @ R.T
    diff = P @ R.T + t - Q
    return float(np.sqrt(np.mean(np.sum(diff ** 2, axis=1)))), R, t
