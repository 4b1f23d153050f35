"""Planarity: ~0 for a planar wave, tan(alpha) and alpha for a wave in a tilted plane,
and a plane that turns over time is followed."""
import numpy as np
import pytest

from mdbridge.analysis import WaveAnalysis, kabsch_rmsd
from mdbridge.analysis.synthetic import E_AXIS, E_IN, E_OUT, helix_trajectory

N_BP, RISE = 158, 3.38
K = 2 * np.pi / (N_BP * RISE)
TIMES = np.arange(0.0, 100.0, 1.0)


def wave(x, t):
    return 5.0 * np.cos(K * x - 0.02 * t)


def test_planar_wave_has_zero_planarity():
    traj, _ = helix_trajectory(TIMES, wave, offset_A=1.5, box_A=80.0)
    r = WaveAnalysis(traj, n_boot=2).run().results
    # The 1.5 A offset helix of a bent duplex is not exactly uniform (each base pair's x
    # axis is perpendicular to the local tangent), which leaves ~1e-5 of out-of-plane axis
    # wiggle; with no offset the planar wave is planar to round-off.
    assert r.planarity["planarity"] < 1e-4
    assert np.max(np.abs(r.planarity["angle_deg"])) < 1e-2
    traj0, _ = helix_trajectory(TIMES, wave, offset_A=0.0, box_A=80.0)
    assert WaveAnalysis(traj0, n_boot=2).run().results.planarity["planarity"] < 1e-12
    assert abs(np.dot(r.e_in, E_IN)) == pytest.approx(1.0, abs=1e-9)  # found from t = 0


def test_tilted_plane_is_measured():
    alpha = np.radians(20.0)
    tilted = np.cos(alpha) * E_IN + np.sin(alpha) * E_OUT
    traj, _ = helix_trajectory(TIMES, wave, offset_A=1.5, e_in=tilted)
    r = WaveAnalysis(traj, in_plane=E_IN, n_boot=2).run().results  # reference plane from the "scene"
    assert r.planarity["planarity"] == pytest.approx(np.tan(alpha), rel=1e-6)
    assert abs(r.planarity["plane_angle_deg"]) == pytest.approx(20.0, abs=1e-6)
    assert np.allclose(np.abs(r.planarity["angle_deg"]), 20.0, atol=1e-6)
    # without a reference plane, the plane of the initial disturbance is the tilted one
    r0 = WaveAnalysis(traj, n_boot=2).run().results
    assert r0.planarity["planarity"] < 1e-4


def test_precessing_plane_is_followed():
    rate = np.radians(0.5)  # degrees per ps
    f_in = lambda x, t: 5.0 * np.cos(K * x) * np.cos(rate * t)  # noqa: E731
    f_out = lambda x, t: 5.0 * np.cos(K * x) * np.sin(rate * t)  # noqa: E731
    traj, _ = helix_trajectory(TIMES, f_in, f_out, offset_A=1.0)
    r = WaveAnalysis(traj, in_plane=E_IN, n_boot=2).run().results
    angle = r.planarity["angle_deg"]
    # helix_trajectory puts u_out along E_OUT = E_AXIS x E_IN, the analysis' e_out too
    assert np.dot(r.e_out, np.cross(E_AXIS, E_IN)) == pytest.approx(1.0)
    np.testing.assert_allclose(angle, np.degrees(rate * TIMES), atol=1e-6)
    assert np.max(r.planarity["svd_ratio"]) < 1e-4  # each frame is planar (offset-helix wiggle aside)


def test_kabsch_recovers_rigid_motion_and_refuses_reflection():
    rng = np.random.default_rng(0)
    P = rng.standard_normal((50, 3)) * 10
    q, _ = np.linalg.qr(rng.standard_normal((3, 3)))
    q *= np.sign(np.linalg.det(q))
    Q = P @ q.T + np.array([1.0, -2.0, 3.0])
    rmsd, R, t = kabsch_rmsd(P, Q)
    assert rmsd < 1e-10
    np.testing.assert_allclose(R, q, atol=1e-10)
    mirrored = P * np.array([1.0, 1.0, -1.0])
    assert kabsch_rmsd(mirrored, P)[0] > 1.0


@pytest.mark.parametrize("sign", [1.0, -1.0])
def test_in_plane_direction_has_a_fixed_sign(sign):
    """The plane of the initial disturbance comes from an SVD, whose sign is arbitrary;
    rod and MD of one scene must get the same e_in, so a kick along -Z or +Z (either sign
    of the same plane) gives +Z, the largest component positive."""
    from mdbridge.analysis.wave_analysis import initial_plane_direction
    n, times = 64, np.arange(6) * 1.0
    s = np.arange(n) * 2 * np.pi / n
    u = np.zeros((len(times), n, 3))
    u[..., 2] = sign * np.outer(times, np.sin(s))       # u = v t, v along +-Z
    u[..., 0] = 0.01 * np.outer(times, np.cos(s))       # a little off-plane
    e_in = initial_plane_direction(u, times)
    assert e_in[2] > 0.99
