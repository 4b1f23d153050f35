"""Base-pair frames for the builder: the uniform ideal helix. Frames from step
parameters are mdbridge.geometry.frames_from_steps (3DNA's composition, done once),
which returns (R, origins) like every frame function of the toolkit."""
from __future__ import annotations

import numpy as np

from dna_models import bdna
from dna_models.errors import InputError
from mdbridge.geometry.steps import frames_from_steps


def ideal_frames(n_bp: int, rise: float = bdna.RISE_A, twist: float = bdna.TWIST_DEG):
    """(R (n_bp, 3, 3), origins (n_bp, 3)) of a uniform helix of n_bp base pairs: every step
    rise (A) and twist (deg), all else 0; base pair 1 at the origin with the lab axes."""
    if n_bp < 1:
        raise InputError(f"number of base pairs {n_bp}: need at least 1")
    steps = np.zeros((n_bp - 1, 6))
    steps[:, 2] = rise
    steps[:, 5] = twist
    return frames_from_steps(steps)
