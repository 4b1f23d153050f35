"""STAND-IN, to be deleted at merge: the shared per-frame analysis base is written on its own
branch (the one loop every per-frame analysis goes through). This file has exactly its API
(Results; AnalysisBase(trajectory, verbose=False).run(start, stop, step, frames, progress)
owning the loop; subclasses implement _prepare, _single_frame (self._frame_index,
self._frame) and _conclude; results in self.results) and nothing more, so that
mdbridge/analysis/modes.py runs unchanged on the real one.
"""
from __future__ import annotations

import numpy as np


class Results(dict):
    """A dict whose keys are also attributes."""

    def __getattr__(self, name):
        try:
            return self[name]
        except KeyError:
            raise AttributeError(name) from None

    def __setattr__(self, name, value):
        self[name] = value


class AnalysisBase:
    def __init__(self, trajectory, verbose: bool = False):
        self._trajectory = trajectory
        self._verbose = verbose
        self.results = Results()

    def _prepare(self):
        pass

    def _single_frame(self):
        raise NotImplementedError

    def _conclude(self):
        pass

    def run(self, start=None, stop=None, step=None, frames=None, progress=None):
        src = self._trajectory
        n_total = len(src.times_ps)
        self.frames = (np.arange(n_total)[slice(start, stop, step)] if frames is None
                       else np.asarray(frames, int))
        self.n_frames = len(self.frames)
        self.results = Results()
        self.times_ps = np.asarray(src.times_ps, float)[self.frames]
        self._prepare()
        for i, frame in enumerate(self.frames):
            self._frame_index, self._frame = i, int(frame)
            self._single_frame()
            if progress is not None:
                progress(i + 1, self.n_frames)
        self._conclude()
        return self
