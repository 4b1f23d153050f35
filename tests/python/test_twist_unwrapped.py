"""Each step's twist is continuous in time wherever twist enters a time series.

3DNA's twist lies in (-180, 180]. A step whose pair has opened can sit near 180 degrees and
cross the cut between two frames: read as given, a 360-degree jump of one step that enters
every twist mode (the committed full-charge record had 55 such spikes). The synthetic duplex
here has one step that rocks across the cut, 179 -> -179 -> 179 ... degrees as 3DNA reports
it, while the true rotation moves by 2 degrees a frame.
"""
import numpy as np

from mdbridge.analysis.modes import ModeAnalysis, frame_modes
from mdbridge.coarsegrain.ensemble import StepEnsemble
from mdbridge.geometry.steps import step_parameters_along, twist_continuous_in_time, unwrap_twist_deg
from mdbridge.geometry.trajectory import BasePairTrajectory

N, RISE, TW = 20, 3.38, 36.0
K = 7            # the step that crosses the cut


def _rz(a_deg):
    a = np.radians(a_deg)
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rocking_duplex(T=40):
    """Straight duplex along z; base pair K + 1 turned by an extra 143 +- 1 degrees, so that
    step K's twist is 179 or 181 degrees (3DNA: 179 or -179) on alternate frames."""
    extra = 143.0 + np.where(np.arange(T) % 2 == 0, 0.0, 2.0)
    R = np.empty((T, N, 3, 3))
    origins = np.zeros((T, N, 3))
    for t in range(T):
        for i in range(N):
            R[t, i] = _rz(TW * i + (extra[t] if i == K + 1 else 0.0))
            origins[t, i, 2] = RISE * i
    period = np.tile([0.0, 0.0, RISE * N], (T, 1))
    return BasePairTrajectory(np.arange(T, dtype=float), origins, R, period), extra


def test_unwrap_takes_the_branch_nearest_the_reference():
    assert unwrap_twist_deg(-179.0, 179.0) == 181.0
    assert unwrap_twist_deg(179.0, -179.0) == -181.0
    assert unwrap_twist_deg(36.0, 34.0) == 36.0
    q = np.zeros((4, 1, 6))
    q[:, 0, 5] = [179.0, -179.0, 179.0, -178.0]
    out = twist_continuous_in_time(q)[:, 0, 5]
    assert np.allclose(np.diff(out), [2.0, -2.0, 3.0])              # continuous, on one branch
    assert np.allclose(np.mod(out, 360.0), np.mod(q[:, 0, 5], 360.0))


def test_a_broken_step_that_wanders_leaves_no_offset_once_closed():
    """A step at 34 degrees breaks, wanders once round the cut (34 -> 170 -> -170 -> -60 ->
    34 as 3DNA reports it, a net full turn of its meaningless broken-pair twist) and closes
    again: afterwards it is at 34 degrees, not 394 (np.unwrap along time would leave 394)."""
    tw = np.concatenate([np.full(50, 34.0), [100, 170, -170, -120, -60, 0], np.full(50, 34.0)])
    q = np.zeros((tw.size, 1, 6))
    q[:, 0, 5] = tw
    out = twist_continuous_in_time(q)[:, 0, 5]
    assert np.allclose(out[-50:], 34.0)
    assert np.allclose(out[51:53], [170.0, 190.0])                  # continuous across +-180
    assert np.allclose(np.degrees(np.unwrap(np.radians(tw)))[-50:], 394.0)   # the control


def test_the_twist_modes_see_no_jump_at_a_step_crossing_the_cut():
    traj, extra = rocking_duplex()
    steps = step_parameters_along(traj.R, traj.origins, periodic=False)
    raw = steps[:, K, 5]
    assert np.all(np.abs(np.abs(raw) - 179.0) < 1e-9)          # 3DNA's branch: +-179
    a = ModeAnalysis(traj, n_max=4).run()
    inc = np.abs(np.diff(a.results.twist, axis=0)).max()
    # the true motion: step K's twist moves by 2 degrees and step K+1's by -2 degrees a frame;
    # the twist density's Fourier amplitudes move by at most (2 / N) 2 * 2 deg / h
    bound = 2.0 / N * 2 * np.radians(2.0) / RISE
    assert inc <= bound * (1 + 1e-9)
    # control, the code before: 3DNA's branch taken as it is puts a 358-degree jump in
    e1, e2 = np.array([1.0, 0, 0]), np.array([0, 1.0, 0])
    w = np.ones(N) / N
    old = np.array([frame_modes(traj.origins[t], traj.R[t], traj.period[t], 4, e1, e2, w, branch=False)[1]
                    for t in range(traj.n_frames)])
    assert np.abs(np.diff(old, axis=0)).max() > 50 * bound


def test_the_coarse_graining_reads_continuous_twist():
    traj, extra = rocking_duplex()
    q = step_parameters_along(traj.R, traj.origins, periodic=False)
    ens = StepEnsemble(q=q, sequence="A" * N, closed=False)
    # step K's twist variance is that of the true +-1-degree rocking, not of a +-179 flip
    assert np.var(ens.q[:, K, 5]) < 1.01
    assert np.var(q[:, K, 5]) > 1e4          # control: the raw series
