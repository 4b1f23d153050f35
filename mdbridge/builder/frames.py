"""Base-pair frames for the builder: from step parameters (3DNA's composition,
done once in mdbridge.geometry) and the uniform ideal helix."""
from __future__ import annotations

import numpy as np

from dna_models import bdna
from dna_models.errors import InputError
from mdbridge.geometry import steps as geometry_steps


def frames_from_steps(steps) -> tuple[np.ndarray, np.ndarray]:
    """Origins (n, 3) and R (n, 3, 3) of n = len(steps) + 1 base pairs from step
    parameters (n - 1, 6): shift, slide, rise (A), tilt, roll, twist (deg).
    Base pair 1 sits at the origin with the lab axes, as in 3DNA's rebuild."""
    steps = np.asarray(steps, dtype=float).reshape(-1, 6)
    if not np.all(np.isfinite(steps)):
        raise InputError("step parameters contain NaN/Inf")
    R, o = geometry_steps.frames_from_steps(steps)
    return o, R


def ideal_frames(n_bp: int, rise: float = bdna.RISE_A, twist: float = bdna.TWIST_DEG):
    """Uniform helix of n_bp base pairs: every step rise (A) and twist (deg), all else 0."""
    if n_bp < 1:
        raise InputError(f"number of base pairs {n_bp}: need at least 1")
    steps = np.zeros((n_bp - 1, 6))
    steps[:, 2] = rise
    steps[:, 5] = twist
    return frames_from_steps(steps)
