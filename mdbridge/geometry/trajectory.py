"""A trajectory of base-pair frames: the one input of the comparison analysis.

Rod output and MD both become a `BasePairTrajectory`:
  times_ps (T), origins (T, n, 3) [A], R (T, n, 3, 3) (columns: x, y, z axes of
  each base pair), period (T, 3) [A] with origin_{i+n} = origin_i + period.
Origins are made continuous along the strand (each is the nearest image of the
one before), so the analysis never sees the periodic box again. This matters
for MD of a ligated duplex: atoms are wrapped and `trjconv -pbc whole` cannot
make an infinite molecule whole (docs/analysis.md), so minimum-image steps between
consecutive base pairs are the only safe way to follow the strand.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from dna_models.errors import InputError
from dna_models.units import Units

from .pbc import minimum_image
from .structure import BasePairFrames


def unwrap_ring(origins: np.ndarray, dimensions: np.ndarray):
    """Continuous origins and the period vector of a closed ring in a periodic box.

    origins: (n, 3) possibly wrapped; dimensions: (6,) MDAnalysis box (a, b, c [A],
    alpha, beta, gamma [deg]). Each step i -> i+1, and the closing step n-1 -> 0, is
    taken as its minimum image (mdbridge.geometry.minimum_image); their sum is the
    lattice vector the duplex spans (the period).
    """
    steps = minimum_image(np.roll(origins, -1, axis=0) - origins, np.asarray(dimensions, float))
    out = np.empty_like(origins, dtype=float)
    out[0] = origins[0]
    out[1:] = origins[0] + np.cumsum(steps[:-1], axis=0)
    return out, steps.sum(axis=0)


@dataclass
class BasePairTrajectory:
    times_ps: np.ndarray
    origins: np.ndarray
    R: np.ndarray
    period: np.ndarray
    source: str = "arrays"
    meta: dict = field(default_factory=dict)

    def __post_init__(self):
        T, n = self.origins.shape[:2]
        if self.R.shape != (T, n, 3, 3) or self.period.shape != (T, 3) or self.times_ps.shape != (T,):
            raise InputError(f"{self.source}: inconsistent shapes: times {self.times_ps.shape}, origins "
                             f"{self.origins.shape}, R {self.R.shape}, period {self.period.shape}")
        if n < 4 or T < 3:
            raise InputError(f"{self.source}: need at least 4 base pairs and 3 frames, got {n} and {T}")

    @property
    def n_frames(self) -> int:
        return len(self.times_ps)

    @property
    def n_bp(self) -> int:
        return self.origins.shape[1]

    def seek(self, frame: int) -> float:
        """The time [ps] of FRAME. With `n_frames` this makes the trajectory a frame source
        of the analyses' one loop (mdbridge/geometry/analysis_base.py); the frames are
        arrays in memory, so there is nothing to read."""
        return float(self.times_ps[frame])

    # -- constructors ------------------------------------------------------
    @classmethod
    def from_periodic_box(cls, times_ps, origins, R, box, source="arrays", meta=None):
        """MD-like input: wrapped origins in a periodic box, (T, 6) MDAnalysis dimensions
        or (T, 3) edge lengths of an orthorhombic box [A]."""
        origins = np.asarray(origins, float)
        box = np.asarray(box, float)
        if box.shape[-1] == 3:
            box = np.concatenate([box, np.full(box.shape[:-1] + (3,), 90.0)], axis=-1)
        box = np.broadcast_to(box, (len(origins), 6))
        unwrapped = np.empty_like(origins)
        period = np.empty((len(origins), 3))
        for t in range(len(origins)):
            unwrapped[t], period[t] = unwrap_ring(origins[t], box[t])
        if np.any(np.linalg.norm(period, axis=1) == 0):
            raise InputError(f"{source}: the base-pair origins do not span the periodic box: "
                             "is the duplex ligated across the periodic boundary?")
        return cls(np.asarray(times_ps, float), unwrapped, np.asarray(R, float), period,
                   source, meta or {})

    @classmethod
    def from_rod(cls, run, n_bp: int, units: Units | None = None):
        """A rod run (mdbridge.rod.run.RodRun, solver units) -> base pairs at s_i = i L / n_bp,
        in A and ps: the run's own `RodRun.trajectory` (the rod layer knows its output;
        geometry, below it, only holds the result)."""
        return run.trajectory(n_bp, units)

    @classmethod
    def from_universe(cls, universe, pairs=None, start=None, stop=None, step=None, progress=None):
        """An MD trajectory: base-pair frames from mdbridge.geometry.BasePairFrames (which
        takes minimum images inside bases and across pairs), box from each frame.
        progress, if given: progress(frames_read, frames_total)."""
        bpf = BasePairFrames(universe, pairs=pairs).run(start=start, stop=stop, step=step, progress=progress)
        r = bpf.results
        if r.box is None:
            raise InputError(f"{universe.filename}: no periodic box; the comparison needs the "
                             "ligated, periodic duplex that `dnarod build-md` makes")
        traj = cls.from_periodic_box(np.asarray(r.time, float), r.origins, r.R, r.box,
                                     source=str(universe.filename),
                                     meta={"kind": "md", "sequence": bpf.sequence})
        traj.meta["pairs"] = bpf.pairs
        return traj
