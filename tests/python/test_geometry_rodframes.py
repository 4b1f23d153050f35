"""Rod <-> base-pair frames (mdbridge.rod.frames) against exact continuous rods:
a uniform helix (closed form via the matrix exponential: exact) and a smooth
periodic wave integrated to 1e-13 (the discrete-to-continuous error must
fall as ds^2)."""
import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.linalg import expm

from dna_models.errors import InputError
from dna_models.units import Units
from mdbridge.rod import frames as rodframes
from mdbridge.geometry import steps
from mdbridge.geometry.rotations import axis_angle_matrix
from mdbridge.rod.run import RodRun

U = Units.paper()


def hat(w):
    return np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])


def uniform_rod(Omega, Gamma, s):
    """Exact centerline and directors of dR/ds = R [Omega]x, dr/ds = R Gamma
    (constant body-frame Omega, Gamma; R(0) = I, r(0) = 0): both from one 4x4
    matrix exponential, r(s) = int_0^s exp(u [Omega]) du Gamma."""
    A = np.zeros((4, 4))
    A[:3, :3] = hat(Omega)
    A[:3, 3] = Gamma
    E = np.array([expm(A * si) for si in s])
    return E[:, :3, 3], E[:, :3, :3]


def test_rod_to_bp_uniform_helix_exact():
    """B-DNA-like rod: Omega = (0, 0, twist/ds), Gamma = (0, 0, 1). The base pairs it
    carries have rise = ds * ell and twist exactly; N = 4 n_bp grid points."""
    n_bp, twist = 21, np.radians(34.3)
    ds = U.length_to_rod(U.rise_A)
    L = n_bp * ds
    N = 4 * n_bp
    s = np.arange(N) * L / N
    r, D = uniform_rod([0, 0, twist / ds], [0, 0, 1.0], s)
    p = rodframes.rod_step_parameters(r[None], D[None], n_bp)
    assert p.shape == (1, n_bp - 1, 6)
    expect = [0, 0, U.rise_A, 0, 0, np.degrees(twist)]
    assert np.abs(p - expect).max() < 1e-12


def test_rod_to_bp_bent_sheared_helix_exact():
    """Constant Omega and Gamma with bend and shear: every step equals the exact
    relative transform exp(ds [Omega]), ds Gamma-integral, as 3DNA parameters."""
    Om = np.array([0.08, -0.05, 0.6])
    Ga = np.array([0.05, 0.02, 1.02])
    n_bp = 10
    ds = 0.7
    s = np.arange(2 * n_bp) * ds / 2
    r, D = uniform_rod(Om, Ga, s)
    p = rodframes.rod_step_parameters(r, D, n_bp, ell_A=U.ell_A)
    r1, D1 = uniform_rod(Om, Ga, [0.0, ds])   # one step from the identity frame
    expect = steps.step_parameters(D1[0], r1[0] * U.ell_A, D1[1], r1[1] * U.ell_A)
    assert np.abs(p - expect).max() < 1e-12
    assert np.all(np.abs(p[:, 3:5]) > 1.0)    # the test really has tilt and roll


def test_rod_grid_must_hold_the_base_pairs():
    with pytest.raises(InputError, match="N must be a multiple of n_bp"):
        rodframes.bp_frames_from_rod(np.zeros((10, 3)), np.tile(np.eye(3), (10, 1, 1)), 4)


def test_frames_to_rod_uniform_helix_exact():
    """Frames of a uniform helix (3DNA steps (0.3, -0.2, 3.38, 2, 3, 36)) closed
    into a ring-like periodic rod: Gamma and Omega constant and equal to the
    exact log of the step, to 1e-13."""
    n = 10
    p = np.tile([0.3, -0.2, 3.38, 2.0, 3.0, 36.0], (n, 1))
    R, o = steps.frames_from_steps(p)
    ds = 0.9
    L = n * ds
    s, Gamma, Omega = rodframes.rod_strains_from_frames(R[:-1], o[:-1], L=L, N=4 * n,
                                                        closing=(R[-1], o[-1]))
    R_rel, o_rel, _ = steps.step_transform(p[0])
    # independent: exp(ds [Omega]) must reproduce the step's rotation, and the
    # uniform-rod integral its translation
    assert np.abs(Omega - Omega[0]).max() < 1e-12 and np.abs(Gamma - Gamma[0]).max() < 1e-12
    assert np.abs(expm(hat(Omega[0]) * ds) - R_rel).max() < 1e-12
    r1, _ = uniform_rod(Omega[0], Gamma[0], [0.0, ds])
    assert np.abs(r1[1] * U.ell_A - o_rel).max() < 1e-11


def _wave_rod(n_bp, L=2 * np.pi):
    """Smooth periodic strains; frames integrated to 1e-13 (DOP853)."""
    k = 2 * np.pi / L

    def Omega(s):
        return np.array([0.3 * np.sin(k * s), 0.2 * np.cos(2 * k * s), 1.0 + 0.1 * np.sin(k * s)])

    def Gamma(s):
        return np.array([0.05 * np.cos(k * s), 0.0, 1.0 + 0.02 * np.sin(3 * k * s)])

    def rhs(s, y):
        R = y[:9].reshape(3, 3)
        return np.concatenate([(R @ hat(Omega(s))).ravel(), R @ Gamma(s)])

    s_bp = np.arange(n_bp + 1) * L / n_bp
    sol = solve_ivp(rhs, (0, L), np.concatenate([np.eye(3).ravel(), np.zeros(3)]),
                    method="DOP853", rtol=1e-13, atol=1e-13, t_eval=s_bp)
    R = sol.y[:9].T.reshape(-1, 3, 3)
    r = sol.y[9:].T
    return R, r, Omega, Gamma, L


def test_frames_to_rod_smooth_wave_second_order():
    errs = []
    for n in (16, 32, 64):
        R, r, Omega, Gamma, L = _wave_rod(n)
        o_A = r * U.ell_A
        s, G, Om = rodframes.rod_strains_from_frames(R[:-1], o_A[:-1], L=L, N=2 * n,
                                                     closing=(R[-1], o_A[-1]))
        exact_Om = np.array([Omega(x) for x in s])
        exact_G = np.array([Gamma(x) for x in s])
        errs.append(max(np.abs(Om - exact_Om).max(), np.abs(G - exact_G).max()))
    order = np.log2(np.array(errs[:-1]) / np.array(errs[1:]))
    assert np.all(order > 1.8) and np.all(order < 2.3), (errs, order)
    assert errs[-1] < 1e-3


def test_open_rod_spline_on_uniform_helix():
    n = 12
    p = np.tile([0.0, 0.0, 3.38, 0.0, 0.0, 36.0], (n - 1, 1))
    R, o = steps.frames_from_steps(p)
    s, G, Om = rodframes.rod_strains_from_frames(R, o, N=n, periodic=False)
    ds = U.length_to_rod(3.38)
    assert np.allclose(Om, [0, 0, np.radians(36.0) / ds], atol=1e-12)
    assert np.allclose(G, [0, 0, 1.0], atol=1e-12)   # default L: rise 3.38 A is Gamma3 = 1


def test_read_rod_frames_hdf5(tmp_path):
    import h5py
    n_bp, twist = 8, np.radians(36.0)
    ds = U.length_to_rod(U.rise_A)
    s = np.arange(2 * n_bp) * n_bp * ds / (2 * n_bp)
    r, D = uniform_rod([0, 0, twist / ds], [0, 0, 1.0], s)
    f = tmp_path / "rod.h5"
    with h5py.File(f, "w") as h:
        h["centerline"] = np.stack([r, r])
        h["directors"] = np.stack([D, D])
        h["s"] = s
        h["time"] = [0.0, 1.0]
        h.attrs["ell_A"] = U.ell_A
    run = RodRun.read(f)
    (R, o), t = run.bp_frames(n_bp), run.time
    assert R.shape == (2, n_bp, 3, 3) and list(t) == [0.0, 1.0]
    assert np.abs(steps.step_parameters_along(R, o)[..., 5] - 36.0).max() < 1e-12
    with h5py.File(tmp_path / "bad.h5", "w") as h:
        h["s"] = s
    with pytest.raises(InputError, match="dataset 'centerline' missing"):
        RodRun.read(tmp_path / "bad.h5").bp_frames(n_bp)


def test_midpoint_components_equal_in_both_frames():
    """The rotation vector of R_i^T R_{i+1} has the same components in frames i
    and i+1 (it is the rotation's own axis): the reason Omega needs no choice of frame."""
    Ri = axis_angle_matrix(np.array([0.0, 0.6, 0.8]), 0.7)
    v = np.array([0.1, -0.3, 0.5])
    Rj = Ri @ expm(hat(v))
    assert np.allclose(Ri @ v, Rj @ v, atol=1e-15)
