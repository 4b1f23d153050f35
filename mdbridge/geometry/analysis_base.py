"""The one loop over trajectory frames that every per-frame analysis goes through.

An analysis is a subclass of `AnalysisBase`. It takes its input and fixed parameters in
`__init__`, and implements three steps; `run()`, which subclasses do not override, calls
them and owns the loop (the pattern of MDAnalysis's AnalysisBase):

    _prepare()       once, after the frames are selected (self.frames, self.n_frames known)
    _single_frame()  once per selected frame, in order: self._frame_index counts the selected
                     frames (0, 1, ..., n_frames - 1: where to store), self._frame is the
                     trajectory's frame number (what to read); the source is at that frame
    _conclude()      once, after the loop: turn what was gathered into self.results

Everything an analysis gives is in `self.results`, a `Results`; `self.times_ps` holds
the times of the frames run. `run()` returns the analysis, so `A(traj).run().results`.

The input (`trajectory`) is a frame source: an object with `n_frames` and `seek(frame)`,
which makes `frame` the current one and returns its time in ps. A
`mdbridge.geometry.BasePairTrajectory` is one (its arrays need no reading: rod and MD
alike); `UniverseFrames` makes an MDAnalysis Universe one (each seek reads the frame, and
its `rewind()`, which run() calls after the loop when a source has one, leaves the
universe at its first frame, as MDAnalysis's own iteration does).

Whole-trajectory analyses: when the per-frame work is one vector operation over all
frames, a subclass sets `_whole_trajectory = True` and does the work in `_conclude()` over
`self.frames` at once; there is then no `_single_frame`, and progress is one step. This
needs a source that holds its frames in memory (`times_ps` an array), so a file-backed
source is refused.
"""
from __future__ import annotations

import sys
from typing import Callable, Optional

import numpy as np

from dna_models.errors import InputError


class Results(dict):
    """What an analysis gives: a dict whose keys are also attributes,
    `r.speed_A_per_ps is r["speed_A_per_ps"]`. A plain dict underneath, so
    `mdbridge.jsonio.write_json` writes it as it is. Keys that would hide a dict method
    (`r.items`, `r.keys`, ...) are refused."""

    def _check_key(self, key):
        if isinstance(key, str) and hasattr(dict, key):
            raise KeyError(f"{key!r} cannot be a result name: it is a method of dict "
                           f"(r.{key} would be ambiguous); choose another name")

    def __init__(self, *args, **kwargs):
        super().__init__()
        self.update(*args, **kwargs)

    def update(self, *args, **kwargs):
        for k, v in dict(*args, **kwargs).items():
            self[k] = v

    def __setitem__(self, key, value):
        self._check_key(key)
        super().__setitem__(key, value)

    def setdefault(self, key, default=None):
        self._check_key(key)
        return super().setdefault(key, default)

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(f"no result {name!r} (results: {', '.join(map(str, self)) or 'none'})") \
                from None

    def __setattr__(self, name, value):
        self[name] = value

    def __delattr__(self, name):
        try:
            del self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __reduce__(self):
        # pickle/copy: rebuild from the items (the attribute hooks above see no __dict__)
        return (type(self), (dict(self),))


def select_frames(n_total: int, start=None, stop=None, step=None, frames=None) -> np.ndarray:
    """Frame numbers (int array) chosen from a trajectory of N_TOTAL frames, either by
    start:stop:step (Python slice rules; a negative step runs backwards) or by FRAMES: integers (negative count from the
    end) or booleans, one per frame. Refuses an empty selection and a frame outside the
    trajectory, naming what was asked."""
    if frames is not None:
        if any(x is not None for x in (start, stop, step)):
            raise InputError("give the frames either as start/stop/step or as a list (frames=...), "
                             "not both")
        f = np.asarray(frames)
        if f.dtype == bool:
            if f.shape != (n_total,):
                raise InputError(f"frames: a boolean selection needs one value per frame "
                                 f"({n_total}), got {f.shape[0] if f.ndim else 'a scalar'}")
            chosen = np.flatnonzero(f)
        else:
            if f.ndim != 1 or (f.size and not np.issubdtype(f.dtype, np.integer)):
                raise InputError(f"frames: a list of frame numbers (integers) or of booleans, got {frames!r}")
            bad = f[(f < -n_total) | (f >= n_total)]
            if bad.size:
                raise InputError(f"frames: {bad[0]} is outside the trajectory "
                                 f"(frames 0 to {n_total - 1}, or -{n_total} to -1 from the end)")
            chosen = np.where(f < 0, f + n_total, f).astype(int)
    else:
        if step == 0:
            raise InputError("step: a number of frames other than 0 (negative runs backwards)")
        chosen = np.arange(n_total)[slice(start, stop, step)]
    if chosen.size == 0:
        raise InputError(f"no trajectory frames selected (of {n_total}; start={start}, stop={stop}, "
                         f"step={step}, frames={frames})")
    return chosen


class UniverseFrames:
    """An MDAnalysis Universe as a frame source: seek(frame) reads that frame into the
    universe's atoms (`universe.atoms.positions`, `universe.dimensions`) and returns its time."""

    def __init__(self, universe):
        self.universe = universe

    @property
    def n_frames(self) -> int:
        return len(self.universe.trajectory)

    def seek(self, frame: int) -> float:
        return float(self.universe.trajectory[int(frame)].time)

    def rewind(self):
        self.universe.trajectory.rewind()


def _stderr_progress(name: str) -> Callable[[int, int], None]:
    """verbose=True without a progress function: a line on stderr every tenth of the run."""
    def show(done, total):
        if done == total or done % max(1, total // 10) == 0:
            print(f"{name}: {done}/{total} frames", file=sys.stderr, flush=True)
    return show


class AnalysisBase:
    """Base of every per-frame analysis (module docstring: the three steps and the loop).

    trajectory: the frame source (a BasePairTrajectory, or UniverseFrames(universe));
    verbose: report progress on stderr when run() is given no progress function."""

    _whole_trajectory = False

    def __init__(self, trajectory, verbose: bool = False):
        self._trajectory = trajectory
        self._verbose = verbose
        self.results = Results()

    def __init_subclass__(cls, **kwargs):
        # One loop: an analysis that brought its own run() could skip or repeat frames
        # behind the caller's back, so a subclass may not define one.
        super().__init_subclass__(**kwargs)
        if "run" in cls.__dict__:
            raise TypeError(f"{cls.__name__} defines run(): an analysis implements _prepare, "
                            "_single_frame and _conclude, and AnalysisBase.run owns the loop "
                            "(mdbridge/geometry/analysis_base.py)")

    # -- the steps a subclass implements -------------------------------------
    def _prepare(self):
        """Set up before the loop (arrays of n_frames rows, say)."""

    def _single_frame(self):
        """Work on the current frame (self._frame_index, self._frame)."""
        raise NotImplementedError(f"{type(self).__name__}: implement _single_frame "
                                  "(or set _whole_trajectory = True)")

    def _conclude(self):
        """Turn what the frames gave into self.results."""

    # -- the loop --------------------------------------------------------------
    def run(self, start=None, stop=None, step=None, frames=None,
            progress: Optional[Callable[[int, int], None]] = None):
        """Analyse the frames start:stop:step (or the list `frames`); progress, if given, is
        called as progress(frames_done, frames_total) after each frame. Returns self."""
        src = self._trajectory
        self.frames = select_frames(src.n_frames, start, stop, step, frames)
        self.n_frames = len(self.frames)
        self.results = Results()
        if progress is None and self._verbose:
            progress = _stderr_progress(type(self).__name__)
        if self._whole_trajectory:
            if not isinstance(getattr(src, "times_ps", None), np.ndarray):
                raise TypeError(f"{type(self).__name__} works on the whole trajectory at once and "
                                f"needs its frames in memory ({type(src).__name__} reads them "
                                "one at a time): give it a BasePairTrajectory")
            self.times_ps = np.asarray(src.times_ps, float)[self.frames]
            self._prepare()
            self._conclude()
            if progress is not None:
                progress(1, 1)
            return self
        self.times_ps = np.empty(self.n_frames)
        self._prepare()
        for i, frame in enumerate(self.frames):
            self._frame_index, self._frame = i, int(frame)
            self.times_ps[i] = src.seek(frame)
            self._single_frame()
            if progress is not None:
                progress(i + 1, self.n_frames)
        if hasattr(src, "rewind"):
            src.rewind()
        self._conclude()
        return self
