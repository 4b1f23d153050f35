"""m-step composition and continuum limits against independent truths.

* Composition: the m-step parameters equal the CEHS step parameters between base
  pairs i and i + m of the frames rebuilt from the steps (mdbridge.geometry,
  3DNA's rebuild), open and closed; an ideal helix composes to (0, 0, m rise, 0, 0,
  m twist) beyond a full turn.
* Continuum: a chain of independent Gaussian bends with A1 / kT = 50 nm and
  A2 / kT = 40 nm per unit length, twisted by 34.3 deg per step, is a worm-like
  chain with persistence length 2 A1 A2 / (A1 + A2) / kT = 44.4 nm (the twist mixes
  the two bend directions); <t(0).t(L)> = exp(-L / l_b) exactly. Its independent
  twist and rise fluctuations give C / kT = 100 nm and S = 1000 pN at every length.
"""
import numpy as np
import pytest

from mdbridge.coarsegrain import CoarseGrain, StepEnsemble
from mdbridge.coarsegrain.composition import compose
from mdbridge.coarsegrain.constants import kT_pN_nm
from mdbridge.coarsegrain.estimator import composite_series
from mdbridge.coarsegrain.prestress import rest_shape
from mdbridge.geometry.steps import frames_from_steps, step_parameters


@pytest.mark.parametrize("closed", [False, True])
def test_composition_equals_frames_i_to_i_plus_m(closed):
    rng = np.random.default_rng(4)
    n = 12
    q = np.column_stack([rng.normal(0, .5, n), rng.normal(0, .6, n), rng.normal(3.3, .2, n),
                         rng.normal(0, 4, n), rng.normal(3, 5, n), rng.normal(34, 4, n)])
    comp = compose(q[None], [1, 2, 3, 4], closed=closed)
    qq = np.concatenate([q, q]) if closed else q
    R, o = frames_from_steps(qq)
    for m, qm in comp.items():
        nw = n if closed else n - m + 1
        assert qm.shape == (1, nw, 6)
        ref = step_parameters(R[:nw], o[:nw], R[m:m + nw], o[m:m + nw])
        assert np.abs(qm[0] - ref).max() < 1e-9


def test_ideal_helix_composes_beyond_a_turn():
    q = np.tile([0.0, 0.0, 3.38, 0.0, 0.0, 36.0], (30, 1))[None]
    series = composite_series(q, [1, 5, 10, 11, 15], False, np.zeros(30, bool))
    for m, (qm, _) in series.items():
        assert np.allclose(qm[0], [0, 0, m * 3.38, 0, 0, m * 36.0], atol=1e-9), m


def test_unwrapped_twist_keeps_the_bend_in_the_true_mid_frame():
    """A helix with roll 3 deg per step (twist 36): to first order in the roll, the
    m-step's bend in the mid-step frame half-way along the TRUE twist is the sum of the
    steps' roll vectors turned into it, roll_m = 3 sum_j cos((j + 1/2 - m/2) 36 deg),
    tilt_m = 0. CEHS alone wraps the twist into (-180, 180] and, past half a turn, puts
    the mid frame 180 deg off (roll of the wrong sign): e.g. m = 11 gives -3 deg, not +3."""
    q = np.tile([0.0, 0.0, 3.38, 0.0, 3.0, 36.0], (16, 1))[None]
    ms = list(range(1, 16))
    series = composite_series(q, ms, False, np.zeros(16, bool))
    for m in ms:
        qm = series[m][0][0, 0]
        j = np.arange(m)
        roll = 3.0 * np.cos(np.radians((j + 0.5 - m / 2) * 36.0)).sum()
        assert abs(qm[4] - roll) < 0.2 + 0.02 * abs(roll) and abs(qm[3]) < 0.05, (m, qm[3:5], roll)
        assert abs(qm[5] - 36.0 * m) < 0.15 * m, (m, qm[5])   # second order in the roll


def _wlc(n_steps, T, rng, A1=50.0, A2=40.0, C_tw=100.0, S=1000.0, h=3.4, twist=34.3):
    kT = kT_pN_nm(300.0)
    sd = lambda A: np.degrees(np.sqrt((h / 10) / A))          # noqa: E731 - rad^2 = L / A
    q = np.zeros((T, n_steps, 6))
    q[..., 0] = rng.normal(0, 0.02, (T, n_steps))
    q[..., 1] = rng.normal(0, 0.02, (T, n_steps))
    q[..., 2] = rng.normal(h, np.sqrt((h / 10) * kT / S) * 10, (T, n_steps))
    q[..., 3] = rng.normal(0, sd(A1), (T, n_steps))
    q[..., 4] = rng.normal(0, sd(A2), (T, n_steps))
    q[..., 5] = rng.normal(twist, sd(C_tw), (T, n_steps))
    return q


def test_known_bend_stiffness_gives_its_persistence_length_at_every_m():
    rng = np.random.default_rng(9)
    q = _wlc(24, 3000, rng)
    cg = CoarseGrain(StepEnsemble(q, "A" * 25), 300.0, m_values=[1, 2, 5, 10, 20], n_boot=100,
                     discard=0).run()
    l_true = 2 * 50 * 40 / 90
    for m, b in cg.results["by_m"].items():
        lt, et = b["physical"]["bend_persistence_length_tangent"], b["physical_err"]["bend_persistence_length_tangent"]
        assert abs(lt - l_true) < 3.5 * et and et < 0.05 * l_true, (m, lt, et)
        # the variance form, 2 L / (var tilt + var roll)
        lv, ev = b["physical"]["bend_persistence_length"], b["physical_err"]["bend_persistence_length"]
        assert abs(lv - l_true) < 3.5 * ev and ev < 0.05 * l_true, (m, lv, ev)
        # twist and stretch from the summed steps (contour length, total twist): the input at every m
        for k, truth in (("torsional_persistence_length", 100.0), ("stretch_modulus", 1000.0)):
            v, e = b["physical"][k], b["physical_err"][k]
            assert abs(v - truth) < 3.5 * e and e < 0.05 * truth, (m, k, v, e)
    # the segment's own chord and CEHS twist: exact at m = 1, then bend contributions lower them
    b1, b20 = cg.results["by_m"][1], cg.results["by_m"][20]
    for k in ("torsional_persistence_length_segment", "stretch_modulus_segment"):
        assert b1["physical"][k] == pytest.approx(b1["physical"][k.replace("_segment", "")], rel=1e-9)
        assert b20["physical"][k] < b20["physical"][k.replace("_segment", "")] - 3 * b20["physical_err"][k]


def test_twist_stretch_coupling_sign():
    """A step that overwinds as it lengthens (positive rise-twist covariance) has g < 0."""
    rng = np.random.default_rng(1)
    C = np.diag([0.01, 0.01, 0.04, 9.0, 16.0, 9.0])
    C[2, 5] = C[5, 2] = 0.3                     # corr 0.5
    x = rng.multivariate_normal([0, 0, 3.4, 0, 0, 34], C, size=(4000, 4))
    cg = CoarseGrain(StepEnsemble(x, "ACGTA"), 300.0, m_values=[1], n_boot=50, discard=0).run()
    g = cg.results["by_m"][1]["physical"]["twist_stretch_coupling"]
    assert g < 0 and abs(g) > 5 * cg.results["by_m"][1]["physical_err"]["twist_stretch_coupling"]


def test_rest_shape_of_a_tilted_harmonic_ensemble():
    """E = 1/2 dq^T K dq - f.q sampled by Metropolis (no Gaussian formula used): the
    corrected mean returns q0 for tension 100 pN and torque 30 pN nm."""
    rng = np.random.default_rng(3)
    K = np.diag(1 / np.array([0.5, 0.5, 0.2, 3.0, 4.0, 3.0]) ** 2)
    K[2, 5] = K[5, 2] = 0.3 * np.sqrt(K[2, 2] * K[5, 5])
    q0 = np.array([0, 0, 3.4, 0, 2, 34.0])
    from mdbridge.coarsegrain.prestress import generalised_force
    f = generalised_force(100.0, 30.0, 300.0)
    E = lambda q: 0.5 * (q - q0) @ K @ (q - q0) - f @ q      # noqa: E731 - in kT
    x, e, out = q0.copy(), E(q0), []
    step = np.array([0.3, 0.3, 0.12, 1.8, 2.4, 1.8])
    for t in range(120000):
        y = x + step * rng.uniform(-1, 1, 6)
        ey = E(y)
        if ey < e or rng.random() < np.exp(e - ey):
            x, e = y, ey
        if t % 10 == 0:
            out.append(x)
    out = np.array(out[1000:])
    r = rest_shape(out.mean(axis=0), np.cov(out.T), 100.0, 30.0, 300.0)
    shift = np.linalg.solve(K, f)
    assert shift[2] > 0.05 and shift[5] > 0.3           # the force moves the mean measurably
    assert np.allclose(r, q0, atol=np.array([.05, .05, .01, .2, .3, .2]))


def test_mass_and_inertia_against_mdanalysis_parallel_axis(tmp_path):
    """Per base pair: mass = MDAnalysis' total mass of the two nucleotides; full inertia
    about the base-pair origin = MDAnalysis' tensor about the centre of mass plus the
    parallel-axis term M (|c|^2 1 - c c^T), turned into the base-pair axes."""
    import warnings
    import MDAnalysis as mda
    from mdbridge.coarsegrain.reader import read_ensemble
    from mdbridge.coarsegrain.synthetic import ar1_steps, write_trajectory
    rng = np.random.default_rng(0)
    K = np.tile(np.diag(1 / np.array([.5, .5, .2, 3, 4, 3.]) ** 2), (5, 1, 1))
    q = ar1_steps(np.tile([0, 0, 3.38, 0, 0, 36.], (5, 1)), K, 3, 0.0, rng)
    pdb, trr = write_trajectory(tmp_path, "ACGTTG", q, None, rng)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        u = mda.Universe(str(pdb), str(trr))
        ens, ex = read_ensemble(u)
    mi, bpf = ex["mass_inertia"], ex["bpf"]
    u.trajectory[0]
    I_frames = []
    for i, (r1, r2) in enumerate(bpf.pairs):
        ag = r1.atoms + r2.atoms
        assert abs(mi["mass"][i] - ag.total_mass()) < 1e-6
        c = ag.center_of_mass() - bpf.results.origins[0, i]
        Icom = ag.moment_of_inertia()
        M = ag.total_mass()
        I_o = Icom + M * (np.dot(c, c) * np.eye(3) - np.outer(c, c))
        R = bpf.results.R[0, i]
        I_frames.append(R.T @ I_o @ R)
    # mi averages frames 0..2; compare frame 0 through a one-frame average
    from mdbridge.coarsegrain.reader import mass_inertia
    one = mass_inertia(bpf, np.array([0]))
    assert np.allclose(one["inertia"], np.array(I_frames), rtol=1e-4, atol=1e-2)
    # slice inertia: I33 = I11 + I22 (perpendicular-axis theorem of a flat section)
    s = one["slice_inertia"]
    assert np.allclose(s[:, 2, 2], s[:, 0, 0] + s[:, 1, 1])
