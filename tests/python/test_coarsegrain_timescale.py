"""Compliance by timescale against known answers (mdbridge/coarsegrain/timescale.py,
docs/coarse-graining.md, "Compliance by timescale").

Truths, each independent of the estimator:
* a pure oscillation of period P: a window of W keeps 1 - sinc^2(pi W / P) of its variance
  (the window mean of cos over W, by hand), which the triangle average of its creep
  compliance A^2 (1 - cos omega u) / 2 must reproduce;
* the synthetic ensemble of mdbridge.coarsegrain.synthetic.fast_slow_steps: fast elastic
  fluctuations (AR(1), correlation time 1 ps, compliance J_fast) plus smooth slow episodes
  (Gaussian-smoothed noise of width sigma, compliance J_slow = 2 J_fast). Its creep
  compliance is known in closed form, so K(W)^-1 is known at every W (the triangle
  average, computed here by quadrature of the closed form), the unrelaxed stiffness is
  J_fast^-1, the relaxed (J_fast + J_slow)^-1, and the dynamic compliance the Debye
  J_fast / (1 + i omega tau) plus the slow part's transform (quadrature).
Controls that must fail: the whole record against the unrelaxed truth; the creep
compliance J(W) against the triangle truth; the relaxed compliance as the storage at omega.
"""
import json
import math
import warnings

import numpy as np
import pytest

from cg_truth import allowed_beyond_3sigma, per_step
from dna_models.errors import InputError
from dnarod.cli import main
from mdbridge.coarsegrain import timescale as ts
from mdbridge.coarsegrain.synthetic import fast_slow_creep, fast_slow_steps, write_trajectory

TAU_FAST_PS = 1.0


def _diag(M):
    return np.diagonal(np.asarray(M, dtype=float), axis1=-2, axis2=-1)


def _truths(seq):
    """J_fast (6, 6): Olson 1998's compliance of the sequence's first dimer; J_slow = 2 J_fast."""
    mean, F = per_step(seq)
    J_fast = np.linalg.inv(F[0])
    return mean, J_fast, 2.0 * J_fast


def _triangle_truth(W_ps, J_fast, J_slow, sigma_ps, dt_ps=1.0):
    """K(W)^-1 of the synthetic ensemble: (2 / n^2) sum_{k<n} (n - k) J(k dt) of its closed-form
    creep compliance, n = W / dt frames (the discrete form; the identity is tested below)."""
    n = int(round(W_ps / dt_ps))
    k = np.arange(1, n)
    J = fast_slow_creep(k * dt_ps, J_fast, J_slow, TAU_FAST_PS, sigma_ps)
    return np.einsum("k,kij->ij", 2.0 * (n - k) / n ** 2, J)


def _dynamic_truth(omega, J_fast, J_slow, sigma_ps):
    """J*(omega) = J_fast / (1 + i omega tau) + J_slow [1 - i omega int_0^inf e^{-u^2 / 4 sigma^2 - i omega u}]."""
    u = np.linspace(0.0, 12.0 * sigma_ps, 200001)
    f = np.exp(-u ** 2 / (4.0 * sigma_ps ** 2) - 1j * omega * u)
    slow_hat = np.sum(0.5 * (f[1:] + f[:-1])) * (u[1] - u[0])
    return J_fast / (1.0 + 1j * omega * TAU_FAST_PS) + J_slow * (1.0 - 1j * omega * slow_hat)


def test_triangle_average_of_an_oscillation_is_the_window_variance():
    """A mode of period P, amplitude A (random phase): its within-window variance is
    A^2 / 2 (1 - sinc^2(pi W / P)); the triangle average of its creep compliance
    A^2 (1 - cos omega u) / 2 must equal it, continuous and discrete (sampled finely).
    Control: the creep compliance at lag W itself differs (by up to 0.6 A^2)."""
    P = 375.0
    for W in (20.0, 100.0, 187.5, 375.0, 1000.0):
        want = 0.5 * (1.0 - np.sinc(W / P) ** 2)            # np.sinc(x) = sin(pi x) / (pi x)
        J = lambda u: 0.5 * (1.0 - np.cos(2 * np.pi * u / P))   # noqa: E731
        got = ts.triangle_average_continuous(J, W)
        n = 4000
        u = np.arange(n + 1) * W / n
        got_discrete = float(ts.triangle_average(J(u), n))
        assert abs(got - want) < 1e-6 and abs(got_discrete - want) < 1e-3 * max(want, 1e-3), (W, got, want)
    assert abs(float(J(np.array(100.0))) - 0.5 * (1.0 - np.sinc(100.0 / P) ** 2)) > 0.05


def test_within_window_variance_is_exactly_the_discrete_triangle_average():
    """The identity behind K(W): for any stationary series, E[window covariance] =
    (2 / n^2) sum_{k<n} (n - k) J(k). On an AR(1) series (phi = 0.6, J(k) = 1 - phi^k
    exactly) averaged over 20000 windows of n = 10: within 3 standard errors. Control:
    the window covariance with divisor n - 1 (the usual sample variance) misses it."""
    rng = np.random.default_rng(0)
    phi, n, n_w = 0.6, 10, 20000
    x = np.empty(n * n_w)
    x[0] = rng.standard_normal()
    e = rng.standard_normal(len(x)) * math.sqrt(1 - phi * phi)
    for t in range(1, len(x)):
        x[t] = phi * x[t - 1] + e[t]
    w = x.reshape(n_w, n)
    v = ((w - w.mean(axis=1, keepdims=True)) ** 2).sum(axis=1) / n
    want = float(ts.triangle_average(1.0 - phi ** np.arange(n), n))
    se = v.std(ddof=1) / math.sqrt(n_w)
    assert abs(v.mean() - want) < 3 * se, (v.mean(), want, se)
    assert abs(v.mean() * n / (n - 1) - want) > 5 * se


# -- the known answer, over realisations (arrays) -----------------------------------------
SIGMA_CAL_PS = 200.0
T_CAL = 40000
W_UNRELAXED_PS = 100.0
OMEGA = 2 * np.pi / 100.0          # a mode of period 100 ps
N_REAL = 8


@pytest.fixture(scope="module")
def realisations():
    """8 independent records of 40 ns at 1 ps (2 bp, one step): K(W) at 20 and 100 ps, the
    record, the creep compliance at 20 ps and J*(2 pi / 100 ps), each with its stated error."""
    mean, J_fast, J_slow = _truths("GA")
    out = []
    for seed in range(N_REAL):
        q = fast_slow_steps(mean, J_fast, J_slow, T_CAL, 1.0, TAU_FAST_PS, SIGMA_CAL_PS, np.random.default_rng(seed))
        r = ts.compliance_by_window(q, np.ones(1, bool), False, 1.0, [20.0, W_UNRELAXED_PS], n_boot=200, seed=seed)
        dj = ts.dynamic_compliance_q0(ts.Coordinates(q, np.ones(1, bool), False), 1.0, [OMEGA], 2400, seed=seed)
        out.append((r, dj))
    return out, J_fast, J_slow


def test_unrelaxed_and_relaxed_stiffness_within_stated_errors(realisations):
    """The known answer: K(100 ps) = J_fast^-1 and K(record) = (J_fast + J_slow)^-1, each within
    its stated error (diagonals of 8 realisations: |z| > 3 no more often than the binomial
    99.9 % bound), and K(W) at 20 and 100 ps = the triangle average of the closed-form
    creep compliance. At 100 ps the triangle truth lies within 0.3 % of J_fast (the fast
    part's 2 tau / W loss and the slow episodes' (W / sigma)^2 / 24 gain nearly cancel,
    each about 2 %), below a third of the stated errors."""
    runs, J_fast, J_slow = realisations
    tri = {W: _triangle_truth(W, J_fast, J_slow, SIGMA_CAL_PS) for W in (20.0, W_UNRELAXED_PS)}
    assert np.all(np.abs(_diag(tri[W_UNRELAXED_PS]) / _diag(J_fast) - 1) < 0.003)
    z_un, z_rel, z_tri = [], [], []
    for r, _ in runs:
        e20, e100 = r["entries"]
        rec = r["record"]
        assert np.all(_diag(e100["stiffness_q0_err"]) < 0.02 * _diag(np.linalg.inv(J_fast)))
        z_un.append((_diag(e100["stiffness_q0"]) - _diag(np.linalg.inv(J_fast))) / _diag(e100["stiffness_q0_err"]))
        z_rel.append((_diag(rec["stiffness_q0"]) - _diag(np.linalg.inv(J_fast + J_slow)))
                     / _diag(rec["stiffness_q0_err"]))
        for e, W in ((e20, 20.0), (e100, W_UNRELAXED_PS)):
            z_tri.append((_diag(e["compliance_q0"]) - _diag(tri[W])) / _diag(e["compliance_q0_err"]))
        assert e100["effective_samples"] > 1000 and rec["effective_samples"] > 20
    for z in (z_un, z_rel, z_tri):
        z = np.ravel(z)
        assert np.sum(np.abs(z) > 3) <= allowed_beyond_3sigma(z.size), z


def test_control_whole_record_misses_the_unrelaxed_truth(realisations):
    """Must fail the test above: the whole-record (relaxed) stiffness is a third of J_fast^-1,
    many of its stated errors away in every realisation and element."""
    runs, J_fast, _ = realisations
    for r, _ in runs:
        rec = r["record"]
        z = (_diag(rec["stiffness_q0"]) - _diag(np.linalg.inv(J_fast))) / _diag(rec["stiffness_q0_err"])
        assert np.all(z < -5), z


def test_stated_errors_are_calibrated_over_realisations(realisations):
    """The scatter of each estimate over the 8 realisations over its rms stated error, per
    diagonal element (7 degrees of freedom: 0.25-2.5 is the chi^2 99.99 % range) and pooled
    over the six as an rms (about 42 degrees of freedom, elements of one realisation being
    correlated: 0.6-1.6)."""
    runs, _, _ = realisations
    names = ("K(100 ps)", "J(20 ps)", "K(record)", "J*' (100 ps)", "J*'' (100 ps)")
    for name, pick in zip(names, (lambda r, d: (r["entries"][1]["stiffness_q0"], r["entries"][1]["stiffness_q0_err"]),
                 lambda r, d: (r["entries"][0]["creep_q0"], r["entries"][0]["creep_q0_err"]),
                 lambda r, d: (r["record"]["stiffness_q0"], r["record"]["stiffness_q0_err"]),
                 lambda r, d: (d["J"][0].real, d["J_storage_err"][0]),
                 lambda r, d: (d["J"][0].imag, d["J_loss_err"][0]))):
        est = np.array([_diag(pick(r, d)[0]) for r, d in runs])
        err = np.array([_diag(pick(r, d)[1]) for r, d in runs])
        ratio = est.std(axis=0, ddof=1) / np.sqrt((err ** 2).mean(axis=0))
        rms = float(np.sqrt(np.mean(ratio ** 2)))
        print(f"scatter / stated error, {name}: {np.round(ratio, 2)}, rms {rms:.2f}")
        assert np.all((ratio > 0.25) & (ratio < 2.5)), (name, ratio)
        assert 0.6 < rms < 1.6, (name, ratio)


def test_creep_compliance_and_dynamic_compliance_return_their_truths(realisations):
    """The creep compliance at 20 ps is J_fast (+ 0.25 % of J_slow) and J*(2 pi / 100 ps) the
    Debye fast part plus the slow episodes' transform: storage 0.99 J_fast, loss 0.063 J_fast
    (diagonals, 8 realisations, binomial 3-sigma bound). Control: the relaxed compliance
    J_fast + J_slow taken as the storage at omega misses by > 10 errors."""
    runs, J_fast, J_slow = realisations
    creep_true = fast_slow_creep(20.0, J_fast, J_slow, TAU_FAST_PS, SIGMA_CAL_PS)
    Jstar = _dynamic_truth(OMEGA, J_fast, J_slow, SIGMA_CAL_PS)
    assert np.allclose(_diag(Jstar.real) / _diag(J_fast), 0.99, atol=0.005)
    z_c, z_s, z_l, z_ctl = [], [], [], []
    for r, d in runs:
        e20 = r["entries"][0]
        z_c.append((_diag(e20["creep_q0"]) - _diag(creep_true)) / _diag(e20["creep_q0_err"]))
        z_s.append((_diag(d["J"][0].real) - _diag(Jstar.real)) / _diag(d["J_storage_err"][0]))
        z_l.append((_diag(d["J"][0].imag) - _diag(Jstar.imag)) / _diag(d["J_loss_err"][0]))
        z_ctl.append((_diag(d["J"][0].real) - _diag(J_fast + J_slow)) / _diag(d["J_storage_err"][0]))
    for z in (z_c, z_s, z_l):
        z = np.ravel(z)
        assert np.sum(np.abs(z) > 3) <= allowed_beyond_3sigma(z.size), z
    assert np.all(np.ravel(z_ctl) < -10)


# -- through atoms and the command ---------------------------------------------------------
SIGMA_MD_PS = 100.0
T_MD = 3000


@pytest.fixture(scope="module")
def md_run(tmp_path_factory):
    """3 bp (2 steps) written as atoms (PDB + TRR, frames 1 ps apart), 3 ns, slow episodes of
    width 100 ps, then `dnarod coarse-grain --window-ps 50 20`."""
    seq = "GAC"
    mean, _ = per_step(seq)
    _, J_fast, J_slow = _truths(seq)
    rng = np.random.default_rng(21)
    q = fast_slow_steps(mean, J_fast, J_slow, T_MD, 1.0, TAU_FAST_PS, SIGMA_MD_PS, rng)
    d = tmp_path_factory.mktemp("timescale")
    pdb, trr = write_trajectory(d / "md", seq, q, None, rng, dt_ps=1.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rc = main(["coarse-grain", str(pdb), str(trr), "-o", str(d / "cg"), "--discard", "0", "--m-max", "1",
                   "--temperature", "300", "--bootstrap", "100", "--window-ps", "50", "20"])
    assert rc == 0
    return json.loads((d / "cg" / "params.json").read_text()), J_fast, J_slow, (pdb, trr, d)


def test_command_writes_the_unrelaxed_and_relaxed_stiffness(md_run):
    """params.json through atoms: the frame time from the trajectory (1 ps), "unrelaxed" at the
    first W given (50 ps) within 3 errors of J_fast^-1, K(W) at every W within 3 errors of the
    triangle truth (binomial bound), the record's (the last entry) within 3 errors of
    (J_fast + J_slow)^-1; the record is short of 50 samples, so it is written with its caveat
    rather than refused. Control: "average"."stiffness" (the whole record) misses J_fast^-1
    by more than 3 of its errors in every element (measured 4.2-9.0)."""
    p, J_fast, J_slow, _ = md_run
    u, cbw = p["unrelaxed"], p["compliance_by_window"]
    assert u["window_ps"] == 50.0 and u["window_frames"] == 50 and cbw["frame_spacing_ps"] == 1.0
    assert np.shape(u["stiffness"]) == (6, 6) and np.shape(u["stiffness_err"]) == (6, 6)
    K_f = np.linalg.inv(J_fast)
    z = (_diag(u["stiffness"]) - _diag(K_f)) / _diag(u["stiffness_err"])
    assert np.all(np.abs(z) < 3), z
    W = cbw["window_ps"]
    assert W[-1] == T_MD * 1.0 and 20.0 in W and 50.0 in W and len(cbw["compliance"]) == len(W)
    zs = [(_diag(c) - _diag(_triangle_truth(w, J_fast, J_slow, SIGMA_MD_PS))) / _diag(e)
          for w, c, e in zip(W[:-1], cbw["compliance"][:-1], cbw["compliance_err"][:-1])]
    assert np.sum(np.abs(np.ravel(zs)) > 3) <= allowed_beyond_3sigma(np.size(zs)), np.round(zs, 1)
    z_rel = (_diag(cbw["stiffness"][-1]) - _diag(np.linalg.inv(J_fast + J_slow))) / _diag(cbw["stiffness_err"][-1])
    assert np.all(np.abs(z_rel) < 3), z_rel
    assert p["effective_samples"] < 50 and any("--window-ps" in c for c in p["caveats"])
    z_ctl = (_diag(p["average"]["stiffness"]) - _diag(K_f)) / _diag(p["average"]["stiffness_err"])
    assert np.all(z_ctl < -3), z_ctl


def test_command_refuses_a_window_the_record_cannot_hold(md_run, capsys):
    """A W that leaves fewer than 8 windows is refused with exit 2, naming the window and
    the longest allowed; without --window-ps the same short record is refused as before."""
    _, _, _, (pdb, trr, d) = md_run
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rc = main(["coarse-grain", str(pdb), str(trr), "-o", str(d / "cg2"), "--discard", "0", "--m-max", "1",
                   "--temperature", "300", "--bootstrap", "20", "--window-ps", "500"])
    assert rc == 2
    err = capsys.readouterr().err
    assert "window 500 ps" in err and "allowed up to 375 ps" in err, err
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rc = main(["coarse-grain", str(pdb), str(trr), "-o", str(d / "cg3"), "--discard", "0", "--m-max", "1",
                   "--temperature", "300", "--bootstrap", "20"])
    assert rc == 2 and "too few frames" in capsys.readouterr().err


def test_default_window_and_its_refusals():
    """Without W: the default 50 ps; a record too short for 8 such windows gives "unrelaxed":
    null with the reason (not an error); a given W on unevenly spaced frames is refused."""
    mean, J_fast, J_slow = _truths("GA")
    q = fast_slow_steps(mean, J_fast, J_slow, 2000, 1.0, TAU_FAST_PS, 100.0, np.random.default_rng(3))
    t = np.arange(2000.0)
    s = ts.params_section(q, np.ones(1, bool), False, t, None, 50.0, n_boot=20)
    assert s["unrelaxed"]["window_ps"] == ts.DEFAULT_WINDOW_PS == 50.0
    short = ts.params_section(q[:300], np.ones(1, bool), False, t[:300], None, 50.0, n_boot=20)
    assert short["unrelaxed"] is None and "too short for the default window 50 ps" in short["unrelaxed_reason"]
    t_gap = t.copy()
    t_gap[1000:] += 7.0
    with pytest.raises(InputError, match="not evenly spaced"):
        ts.params_section(q, np.ones(1, bool), False, t_gap, [50.0], 50.0, n_boot=20)


def test_leaving_a_mode_out_refits_the_intercept():
    """Rule 3: the mode's own wavenumber leaves the q -> 0 fit and the intercept is refitted
    over the rest. Truth: on independent steps S(q) is flat, so the intercept is the same
    compliance with or without the mode (within errors); the weights still sum to one and
    the left-out mode carries none. Control: the fit modes do change."""
    rng = np.random.default_rng(2)
    seq = "".join(rng.choice(list("ACGT"), 64))
    mean, F = per_step(seq)
    q = fast_slow_steps(mean, np.linalg.inv(F[0]), 0.01 * np.linalg.inv(F[0]), 3000, 1.0, TAU_FAST_PS, 100.0, rng)
    full = ts.Coordinates(q, np.ones(63, bool), False)
    out = ts.Coordinates(q, np.ones(63, bool), False, leave_out=2)
    assert 2 in full.modes and 2 not in out.modes and len(out.modes) == len(full.modes) - 1
    assert abs(out.weights.sum() - 1) < 1e-12 and abs(full.weights.sum() - 1) < 1e-12
    a = ts.window_compliance(full, 20, 50, np.random.default_rng(0))
    b = ts.window_compliance(out, 20, 50, np.random.default_rng(0))
    z = (_diag(a["compliance_q0"]) - _diag(b["compliance_q0"])) / _diag(b["compliance_q0_err"])
    assert np.all(np.abs(z) < 3), z
