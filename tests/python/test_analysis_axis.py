"""Helical axis from base-pair origins (one-turn window) against known axes."""
import numpy as np
import pytest

from mdbridge.analysis import WaveAnalysis, helical_axis, mean_twist, one_turn_weights
from mdbridge.analysis.axis import window_response
from mdbridge.analysis.synthetic import helix_trajectory

N_BP, TURNS, RISE = 158, 15, 3.38
L = N_BP * RISE
K = 2 * np.pi / L


def test_mean_twist_and_window():
    traj, _ = helix_trajectory([0.0, 1.0, 2.0], lambda x, t: 0 * x, n=N_BP, turns=TURNS)
    theta = mean_twist(traj.R[0])
    assert theta == pytest.approx(2 * np.pi * TURNS / N_BP, rel=1e-12)
    w = one_turn_weights(theta, N_BP)
    assert w.sum() == pytest.approx(1.0)
    assert window_response(w, theta) == pytest.approx(0.0, abs=1e-12)  # a helix of the twist is removed
    # total window length is one turn (to within the end-weight adjustment)
    assert (len(w) - 2 + 2 * w[0] / w[1]) == pytest.approx(N_BP / TURNS, abs=0.1)


def test_offset_helix_of_origins_gives_the_straight_axis_exactly():
    """Origins 2 A off the axis along each base pair's x axis (an ideal helix): the
    window removes the offset to round-off."""
    traj, exact = helix_trajectory([0.0, 1.0, 2.0], lambda x, t: 0 * x, offset_A=2.0)
    a, _ = helical_axis(traj.origins[0], traj.R[0], traj.period[0])
    assert np.max(np.abs(a - exact[0])) < 1e-10


def test_displaced_helix_axis_within_window_smoothing():
    """A bent duplex (5 A sinusoidal axis) with a 2 A offset helix: the axis is recovered
    to the window's smoothing of the displacement, (1 - H(k)) * 5 A, plus 0.01 A."""
    amp = 5.0
    traj, exact = helix_trajectory([0.0, 1.0, 2.0], lambda x, t: amp * np.cos(K * x), offset_A=2.0)
    a, w = helical_axis(traj.origins[0], traj.R[0], traj.period[0])
    bound = (1 - window_response(w, 2 * np.pi / N_BP)) * amp + 0.01
    err = np.max(np.linalg.norm(a - exact[0], axis=1))
    assert err < bound
    assert bound < 0.05  # the stated accuracy: 1 % of the amplitude for 158 bp, 15 turns


def test_wrapped_origins_in_a_box_give_the_same_axis():
    """MD keeps atoms wrapped: minimum-image unwrapping recovers the same axis (up to a
    lattice translation) and the period vector of the ligated duplex."""
    f = lambda x, t: 6.0 * np.cos(K * x - 0.02 * t)  # noqa: E731
    times = np.arange(0.0, 20.0, 1.0)
    free, _ = helix_trajectory(times, f, offset_A=1.5)
    boxed, _ = helix_trajectory(times, f, offset_A=1.5, box_A=60.0)
    np.testing.assert_allclose(boxed.period, free.period, atol=1e-9)
    ra = WaveAnalysis(free, n_boot=2).run().results
    rb = WaveAnalysis(boxed, n_boot=2).run().results
    np.testing.assert_allclose(rb.u_in, ra.u_in, atol=1e-9)
    np.testing.assert_allclose(rb.u_out, ra.u_out, atol=1e-9)


def test_rod_like_origins_reproduce_the_centerline():
    """Rod base pairs sit on the centerline (no offset): the same window reproduces the
    centerline to (1 - H(k)) of the displacement amplitude (0.74 % here)."""
    amp = 8.0
    traj, exact = helix_trajectory([0.0, 1.0, 2.0], lambda x, t: amp * np.sin(K * x), offset_A=0.0)
    a, w = helical_axis(traj.origins[0], traj.R[0], traj.period[0])
    rel = np.max(np.linalg.norm(a - exact[0], axis=1)) / amp
    assert rel == pytest.approx(1 - window_response(w, 2 * np.pi / N_BP), rel=0.02)
    assert rel < 0.01
