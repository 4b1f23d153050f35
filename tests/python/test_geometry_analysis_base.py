"""The one loop of every per-frame analysis (mdbridge/geometry/analysis_base.py).

The truth for frame selection is Python's own slice of range(n) (and, for a list of
frames, the list itself); the truth for what a frame holds is the trajectory's arrays
(or, for an MDAnalysis Universe, MDAnalysis's own whole-trajectory read). A control
analysis that skips frames must be caught by the same check, and one that brings its
own loop is refused when its class is made.
"""
import copy
import json
import pickle

import numpy as np
import pytest

from dna_models.errors import InputError
from mdbridge.geometry.analysis_base import AnalysisBase, Results, UniverseFrames, select_frames
from mdbridge.geometry.trajectory import BasePairTrajectory
from mdbridge.jsonio import dumps

N_FRAMES, N_BP = 11, 6


def _trajectory():
    """Times uneven (so a frame's time names the frame), origins carrying the frame number."""
    rng = np.random.default_rng(3)
    times = np.cumsum(rng.uniform(0.5, 2.0, N_FRAMES))
    origins = np.zeros((N_FRAMES, N_BP, 3))
    origins[:, :, 0] = np.arange(N_FRAMES)[:, None]
    origins[:, :, 1] = np.arange(N_BP) * 3.38
    R = np.broadcast_to(np.eye(3), (N_FRAMES, N_BP, 3, 3)).copy()
    period = np.tile([0.0, N_BP * 3.38, 0.0], (N_FRAMES, 1))
    return BasePairTrajectory(times, origins, R, period)


class Recorder(AnalysisBase):
    """Records, per call of _single_frame, where it stores, what frame it reads and what
    the frame holds; the number of runs of _prepare/_conclude."""

    def _prepare(self):
        self.calls = []
        self.seen = np.full(self.n_frames, -1)

    def _single_frame(self):
        tr = self._trajectory
        self.calls.append((self._frame_index, self._frame, self.times_ps[self._frame_index]))
        self.seen[self._frame_index] = tr.origins[self._frame, 0, 0]

    def _conclude(self):
        self.results.seen = self.seen
        self.results.n_calls = len(self.calls)


class SkipsFrames(Recorder):
    """Control: an analysis that silently drops every other frame."""

    def _single_frame(self):
        if self._frame_index % 2:
            return
        super()._single_frame()


def saw_exactly(a: Recorder, traj: BasePairTrajectory, expected) -> bool:
    """The analysis was called once per expected frame, in order, stored each at its
    place, read that frame's data and was given that frame's time."""
    expected = list(expected)
    return (a.n_frames == len(expected)
            and [c[1] for c in a.calls] == expected
            and [c[0] for c in a.calls] == list(range(len(expected)))
            and np.array_equal(a.results.seen, np.asarray(expected, float))
            and np.array_equal(a.times_ps, traj.times_ps[expected])
            and a.results.n_calls == len(expected))


SELECTIONS = [dict(), dict(start=2), dict(stop=5), dict(start=1, stop=9, step=3), dict(step=4),
              dict(start=-4), dict(start=3, stop=-2, step=2), dict(stop=100), dict(step=-3)]


@pytest.mark.parametrize("sel", SELECTIONS, ids=str)
def test_subclass_sees_exactly_the_selected_frames(sel):
    traj = _trajectory()
    expected = list(range(N_FRAMES))[slice(sel.get("start"), sel.get("stop"), sel.get("step"))]
    a = Recorder(traj)
    assert a.run(**sel) is a                       # run() returns the analysis
    assert saw_exactly(a, traj, expected)
    assert list(a.frames) == expected
    # the control that skips frames is caught by the same check (whenever it can skip)
    if len(expected) > 1:
        assert not saw_exactly(SkipsFrames(traj).run(**sel), traj, expected)


@pytest.mark.parametrize("frames, expected", [([7, 2, 9], [7, 2, 9]), ([-1, 0], [N_FRAMES - 1, 0]),
                                              ([i % 3 == 0 for i in range(N_FRAMES)], [0, 3, 6, 9])])
def test_frames_as_a_list_or_mask(frames, expected):
    traj = _trajectory()
    a = Recorder(traj).run(frames=frames)
    assert saw_exactly(a, traj, expected)
    assert not saw_exactly(SkipsFrames(traj).run(frames=frames), traj, expected)


def test_results_are_fresh_on_every_run():
    a = Recorder(_trajectory()).run()
    a.results.left_over = 1.0
    first = a.results
    a.run(start=5)
    assert "left_over" not in a.results and a.results is not first
    assert a.results.n_calls == N_FRAMES - 5 and len(a.calls) == N_FRAMES - 5   # _prepare ran again
    assert first.n_calls == N_FRAMES                                             # the old one untouched


def test_progress_after_every_frame():
    calls = []
    Recorder(_trajectory()).run(step=2, progress=lambda done, total: calls.append((done, total)))
    n = len(range(0, N_FRAMES, 2))
    assert calls == [(k, n) for k in range(1, n + 1)]


def test_verbose_reports_on_stderr(capsys):
    Recorder(_trajectory(), verbose=True).run()
    assert f"Recorder: {N_FRAMES}/{N_FRAMES} frames" in capsys.readouterr().err
    Recorder(_trajectory()).run()
    assert capsys.readouterr().err == ""


class WholeMean(AnalysisBase):
    """A vectorised analysis: the mean x origin over the selected frames, at once."""
    _whole_trajectory = True

    def _conclude(self):
        self.results.mean_x = self._trajectory.origins[self.frames, :, 0].mean(axis=1)


def test_whole_trajectory_analysis_sees_the_selection_and_one_progress_step():
    traj = _trajectory()
    calls = []
    a = WholeMean(traj).run(start=1, step=3, progress=lambda d, t: calls.append((d, t)))
    assert np.array_equal(a.results.mean_x, np.arange(1, N_FRAMES, 3))
    assert np.array_equal(a.times_ps, traj.times_ps[1::3]) and calls == [(1, 1)]


def test_a_subclass_with_its_own_loop_is_refused():
    with pytest.raises(TypeError, match="defines run"):
        class OwnLoop(Recorder):   # noqa: F841 - the class statement itself must fail
            def run(self, *args, **kwargs):
                for self._frame_index, self._frame in enumerate(range(0, N_FRAMES, 2)):
                    self._single_frame()
                return self


def test_bad_selections_are_refused():
    traj = _trajectory()
    for kw, msg in [(dict(start=N_FRAMES), "no trajectory frames selected"),
                    (dict(frames=[]), "no trajectory frames selected"),
                    (dict(frames=[1], start=0), "not both"),
                    (dict(frames=[N_FRAMES]), f"{N_FRAMES} is outside the trajectory"),
                    (dict(frames=[True, False]), "one value per frame"),
                    (dict(frames=[0.5]), "integers"),
                    (dict(step=0), "other than 0")]:
        with pytest.raises(InputError, match=msg):
            Recorder(traj).run(**kw)
    assert list(select_frames(5, frames=np.array([4, -5]))) == [4, 0]


def test_results_are_a_dict_with_attributes():
    r = Results(speed_A_per_ps=1.5)
    r.wave = {"n": 2}
    assert r.speed_A_per_ps == r["speed_A_per_ps"] == 1.5 and r["wave"] is r.wave
    assert isinstance(r, dict) and sorted(r) == ["speed_A_per_ps", "wave"]
    with pytest.raises(AttributeError, match="no result 'missing'"):
        r.missing
    for bad in ("items", "keys", "update"):
        with pytest.raises(KeyError, match="method of dict"):
            r[bad] = 1
    with pytest.raises(KeyError, match="method of dict"):
        Results({"get": 1})
    del r.wave
    assert "wave" not in r
    r.x = np.array([1.0, np.nan])
    assert json.loads(dumps(r)) == {"speed_A_per_ps": 1.5, "x": [1.0, None]}
    for twin in (pickle.loads(pickle.dumps(r)), copy.deepcopy(r), copy.copy(r)):
        assert type(twin) is Results and twin.speed_A_per_ps == 1.5 and np.array_equal(twin.x, r.x,
                                                                                         equal_nan=True)


def test_universe_frames_read_each_selected_frame():
    """An MDAnalysis Universe through UniverseFrames: each _single_frame sees the atoms of
    its frame, as MDAnalysis's own read of the whole trajectory gives them."""
    from mdbridge.geometry.synthetic import duplex_universe
    rng = np.random.default_rng(0)
    p = np.tile([0, 0, 3.38, 0, 0, 36.0], (6, 3, 1)) + rng.normal(0, 0.5, (6, 3, 6))
    u = duplex_universe("CGAT", p)
    truth = u.trajectory.timeseries(order="fac")

    class Positions(AnalysisBase):
        def _prepare(self):
            self.results.xyz = np.empty((self.n_frames,) + truth.shape[1:])

        def _single_frame(self):
            self.results.xyz[self._frame_index] = self._trajectory.universe.atoms.positions

    a = Positions(UniverseFrames(u)).run(frames=[4, 1, 5])
    assert np.array_equal(a.results.xyz, truth[[4, 1, 5]])
    assert u.trajectory.frame == 0                     # left at the first frame, as MDAnalysis leaves it
    assert np.array_equal(a.times_ps, [u.trajectory[i].time for i in (4, 1, 5)])
    with pytest.raises(TypeError, match="needs its frames in memory"):
        WholeMean(UniverseFrames(u)).run()
