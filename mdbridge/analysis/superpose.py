"""Optimal superposition (Kabsch) of one curve onto another and the RMSD after it.

The fit itself is mdbridge.geometry.basefit.fit_frames (the project's one
least-squares rigid fit, also used for the base frames); this adds the curve
vocabulary (rmsd, R, t)."""
from __future__ import annotations

import numpy as np

from mdbridge.geometry.basefit import fit_frames


def kabsch_rmsd(P: np.ndarray, Q: np.ndarray):
    """RMSD [same units] of points P (n, 3) optimally rotated and translated onto Q (n, 3).

    Returns (rmsd, R, t) with Q ~ P @ R.T + t. R is a proper rotation (no reflection).
    """
    R, t, rmsd = fit_frames(np.asarray(P, float), np.asarray(Q, float), method="svd")
    return float(rmsd), R, t
