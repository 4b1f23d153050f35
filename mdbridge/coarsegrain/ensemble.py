"""`StepEnsemble`: what the coarse-graining estimates from -- step parameters of a
duplex along an equilibrium trajectory, and which steps may be used."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dna_models.errors import InputError
from mdbridge.geometry.steps import twist_continuous_in_time


@dataclass
class StepEnsemble:
    """q (T, n_steps, 6): shift, slide, rise [A], tilt, roll, twist [deg] per frame and
    step (3DNA definitions); step k joins base pairs k and k + 1 (0-based), and for a
    closed (periodic ligated) duplex n_steps == n_bp and the last step joins the last
    base pair to the first. excluded (n_steps,) bool: steps not to be used at all;
    opened (n_steps,) bool: steps touching a base pair that the opening rule counts as
    opened: used, and left out only for the rule's sensitivity (estimator.py);
    open_frames (T, n_steps) bool: the frames in which a step touches an open pair (N1-N3 >
    3.5 A, mdbridge/md/integrity.py): left out of that step's local estimates, frame by
    frame (docs/coarse-graining.md); times_ps (T,)."""

    q: np.ndarray
    sequence: str
    closed: bool = False
    times_ps: np.ndarray | None = None
    excluded: np.ndarray | None = None
    opened: np.ndarray | None = None
    open_frames: np.ndarray | None = None
    source: str = "arrays"
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        self.q = np.asarray(self.q, dtype=float)
        if self.q.ndim != 3 or self.q.shape[-1] != 6:
            raise InputError(f"{self.source}: step parameters must be (frames, steps, 6), got {self.q.shape}")
        T, n, _ = self.q.shape
        want = len(self.sequence) if self.closed else len(self.sequence) - 1
        if n != want:
            raise InputError(f"{self.source}: {n} steps for a {'closed' if self.closed else 'linear'} "
                             f"duplex of {len(self.sequence)} bp (expected {want})")
        if not np.all(np.isfinite(self.q)):
            raise InputError(f"{self.source}: step parameters contain NaN/Inf")
        # each step's twist continuous in time (a broken step's 3DNA twist crossing +-180
        # degrees is no motion), before any mean or covariance is taken
        self.q = twist_continuous_in_time(self.q)
        self.times_ps = np.arange(T, dtype=float) if self.times_ps is None else np.asarray(self.times_ps, float)
        if self.times_ps.shape != (T,):
            raise InputError(f"{self.source}: times_ps of shape {self.times_ps.shape} for {T} frames "
                             "of step parameters")
        of = np.zeros((T, n), dtype=bool) if self.open_frames is None else np.asarray(self.open_frames, dtype=bool)
        if of.shape != (T, n):
            raise InputError(f"{self.source}: 'open_frames' has shape {of.shape}, expected ({T}, {n}) "
                             "(one per frame and step)")
        self.open_frames = of
        for name in ("excluded", "opened"):
            v = getattr(self, name)
            v = np.zeros(n, dtype=bool) if v is None else np.asarray(v, dtype=bool)
            if v.shape != (n,):
                raise InputError(f"{self.source}: '{name}' has shape {v.shape}, expected ({n},) (one per step)")
            setattr(self, name, v)

    @property
    def n_frames(self) -> int:
        return self.q.shape[0]

    @property
    def n_steps(self) -> int:
        return self.q.shape[1]

    def dimer(self, k: int) -> str:
        s = self.sequence
        return s[k] + s[(k + 1) % len(s)]
