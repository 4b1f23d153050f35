"""Coarse-graining against ensembles with a known answer.

Truth: step parameters drawn from Gaussians with known per-step means and coupled
6x6 stiffness K (Olson et al. 1998's own tables, tests/data/olson1998/), as an AR(1) series
in time, so the bootstrap must handle correlated frames. One test goes through atoms:
builder -> PDB + TRR with Maxwell-Boltzmann velocities -> `dnarod coarse-grain`.
"""
import json
import warnings

import numpy as np
import pytest

from cg_truth import UPPER, allowed_beyond_3sigma, per_step, z_scores
from mdbridge.coarsegrain import CoarseGrain, StepEnsemble
from mdbridge.coarsegrain.synthetic import ar1_steps, write_trajectory
from dnarod.cli import main


def _fraction_beyond(z):
    z = np.concatenate([np.ravel(x) for x in z])
    return int(np.sum(np.abs(z) > 3.0)), z.size


def test_atoms_trajectory_recovers_means_and_stiffness(tmp_path):
    """8 bp, 1000 frames, phi = 0.8 (tau_int = 4.5 frames), 310 K velocities: per-step
    means (6) and K upper triangles (21) of 7 steps = 189 elements, judged by z-scores;
    the kinetic temperature is read from the TRR's velocities."""
    seq = "GACTAGCA"
    rng = np.random.default_rng(11)
    mean, K = per_step(seq)
    q = ar1_steps(mean, K, 1000, 0.8, rng)
    pdb, trr = write_trajectory(tmp_path / "md", seq, q, 310.0, rng)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        rc = main(["coarse-grain", str(pdb), str(trr), "-o", str(tmp_path / "cg"), "-m", "3", "--discard", "0"])
    assert rc == 0
    p = json.loads((tmp_path / "cg" / "params.json").read_text())
    assert p["temperature_source"] == "kinetic"
    # every frame is at exactly 310 K with 3N - 3 degrees of freedom (gromacs.velocities); read with 3N
    assert abs(p["temperature_K"] - 310.0 * (3 * 328 - 3) / (3 * 328)) < 0.01
    assert p["order"] == ["shift", "slide", "rise", "tilt", "roll", "twist"]
    assert p["frames_used"] == 1000 and not p["closed"]
    zs = []
    for k, s in enumerate(p["steps"]):
        assert s["dimer"] == seq[k:k + 2]
        zs.append(z_scores(s["mean"], s["mean_err"], mean[k]))
        zs.append(z_scores(np.array(s["stiffness"])[UPPER], np.array(s["stiffness_err"])[UPPER], K[k][UPPER]))
    bad, n = _fraction_beyond(zs)
    assert n == 189
    assert bad <= allowed_beyond_3sigma(n), f"{bad} of {n} elements beyond 3 sigma"
    # the rod's K is the truths in series: the inverse of their mean compliance
    series = np.linalg.inv(np.linalg.inv(K).mean(axis=0))
    za = z_scores(np.diagonal(np.array(p["average"]["stiffness"])),
                  np.diagonal(np.array(p["average"]["stiffness_err"])), np.diagonal(series))
    assert np.all(np.abs(za) < 4)
    # stationary input: the two halves agree, the convergence series ends at the full value
    h = p["halves"]
    assert np.all(np.abs(h["z_mean"]) < 4) and np.all(np.abs(h["z_stiffness_diag"]) < 4)
    last = p["convergence"]["physical"]["bend_persistence_length"][-1]
    assert p["convergence"]["frames"][-1] == 1000 and p["convergence"]["m"] == p["physical_m"] == 3
    assert abs(last - p["physical"]["bend_persistence_length"]["value"]) < 1e-6 * last
    assert (tmp_path / "cg" / "convergence.png").stat().st_size > 10000
    assert (tmp_path / "cg" / "by_length.png").stat().st_size > 10000


def _realisation(seed, phi, T, block=None):
    rng = np.random.default_rng(seed)
    seq = "ACGT"
    mean, K = per_step(seq)
    q = ar1_steps(mean, K, T, phi, rng)
    cg = CoarseGrain(StepEnsemble(q, seq), 300.0, m_values=[1], n_boot=100, seed=seed, block=block,
                     discard=0).run()
    b = cg.results["by_m"][1]
    est = np.concatenate([b["mean"].ravel(), np.diagonal(b["K"], axis1=1, axis2=2).ravel()])
    err = np.concatenate([b["mean_err"].ravel(), np.diagonal(b["K_err"], axis1=1, axis2=2).ravel()])
    return est, err


@pytest.fixture(scope="module")
def realisations():
    """24 independent AR(1) realisations (phi = 0.9, tau_int = 9.5 frames, 2000 frames,
    3 steps): means and K diagonals, 36 elements; stated errors with the block length
    from the autocorrelation and, as the control, with frames treated as independent."""
    runs = [_realisation(s, 0.9, 2000) for s in range(24)]
    iid = [_realisation(s, 0.9, 2000, block=1) for s in range(24)]
    return np.array([r[0] for r in runs]), np.array([r[1] for r in runs]), np.array([r[1] for r in iid])


def test_scatter_over_realisations_matches_stated_errors(realisations):
    est, err, _ = realisations
    ratio = est.std(axis=0, ddof=1) / np.sqrt((err ** 2).mean(axis=0))
    assert np.all((ratio > 0.5) & (ratio < 2.0)), ratio
    assert 0.75 < np.median(ratio) < 1.33, np.median(ratio)


def test_control_independent_frames_understate_errors(realisations):
    """Must fail the test above: the ordinary bootstrap ignores the correlation, and
    its errors are too small by ~sqrt(2 tau) (4.4 for the means, 3.1 for K)."""
    est, _, err_iid = realisations
    ratio = est.std(axis=0, ddof=1) / np.sqrt((err_iid ** 2).mean(axis=0))
    assert np.median(ratio) > 2.0, np.median(ratio)
    assert np.mean(ratio > 2.0) > 0.8


def test_olson_crystal_gaussian_returns_its_force_constants():
    """Olson 1998's own Gaussian (means and force constants of all 16 dimers; 17-bp
    sequence holding each dimer once), 4000 independent frames: the estimator returns
    the force constants (16 x 21 = 336 upper-triangle elements + 96 means by z-score)."""
    seq = "AACAGATCCGCTGGTTA"
    mean, F = per_step(seq)
    assert len({seq[k:k + 2] for k in range(16)}) == 16
    rng = np.random.default_rng(5)
    q = ar1_steps(mean, F, 4000, 0.0, rng)
    cg = CoarseGrain(StepEnsemble(q, seq), 298.0, m_values=[1], n_boot=200, seed=1, discard=0).run()
    b = cg.results["by_m"][1]
    bad, n = _fraction_beyond([z_scores(b["K"][:, UPPER[0], UPPER[1]], b["K_err"][:, UPPER[0], UPPER[1]],
                                        F[:, UPPER[0], UPPER[1]]),
                               z_scores(b["mean"], b["mean_err"], mean)])
    assert n == 432
    assert bad <= allowed_beyond_3sigma(n), f"{bad} of {n} beyond 3 sigma"
    # relative accuracy of the diagonal force constants: sqrt(2 / 4000) = 2.2 % each
    rel = np.abs(np.diagonal(b["K"], axis1=1, axis2=2) / np.diagonal(F, axis1=1, axis2=2) - 1)
    assert rel.max() < 0.1


def test_bias_correction_of_inverse_covariance():
    """Wishart truth: for N = 40 independent 6-d Gaussian frames, kT S^-1 overestimates
    K by (N - 1) / (N - 8) = 1.22; the corrected estimator is unbiased (600 draws:
    the mean of the diagonal is within 2 % of the truth)."""
    from mdbridge.coarsegrain.stiffness import stiffness
    rng = np.random.default_rng(2)
    _, F = per_step("GC")
    C = np.linalg.inv(F[0])
    L = np.linalg.cholesky(C)
    N, draws = 40, 600
    x = np.einsum("ij,dtj->dti", L, rng.standard_normal((draws, N, 6)))
    d = x - x.mean(axis=1, keepdims=True)
    S = np.einsum("dti,dtj->dij", d, d) / (N - 1)
    raw = stiffness(S).mean(axis=0)
    cor = stiffness(S, n_eff=N).mean(axis=0)
    assert np.allclose(np.diagonal(raw) / np.diagonal(F[0]), (N - 1) / (N - 8), rtol=0.04)
    assert np.allclose(np.diagonal(cor) / np.diagonal(F[0]), 1.0, atol=0.02)


def test_too_few_frames_is_a_clear_error():
    from dna_models.errors import InputError
    rng = np.random.default_rng(0)
    mean, K = per_step("ACGT")
    q = ar1_steps(mean, K, 300, 0.9, rng)          # tau ~ 9.5: worth ~16 frames
    with pytest.raises(InputError, match=r"too few frames.*at least 50 are needed, i.e. about \d+ frames"):
        CoarseGrain(StepEnsemble(q, "ACGT"), 300.0, m_values=[1], discard=0).run()


def test_block_replicates_equal_explicitly_resampled_frames():
    """The cumulative-sum replicate moments equal numpy's mean and covariance of the
    frames the blocks select (T = 103 not a multiple of b = 10: the last block is cut)."""
    from mdbridge.stats import block_starts, replicate_moments
    rng = np.random.default_rng(0)
    q = rng.normal(size=(103, 4, 6))
    st = block_starts(103, 10, 5, rng)
    m, c = replicate_moments(q, st, 10)
    for r in range(5):
        idx = np.concatenate([np.arange(s, s + 10) for s in st[r]])[:103]
        x = q[idx]
        assert np.allclose(m[r], x.mean(axis=0), atol=1e-12)
        for w in range(4):
            assert np.allclose(c[r, w], np.cov(x[:, w].T), atol=1e-12)


def test_equilibration_drift_is_discarded():
    """The first frames relax from a displaced state (twist +20 deg, rise +1 A decaying
    with a 150-frame time constant): the rule discards them and the mean comes back within
    its errors; the control keeps every frame (discard 0): its mean is off by more than 3
    errors of the equilibrium estimate (its own errors grow too: the drift looks like a
    slow correlation)."""
    rng = np.random.default_rng(8)
    seq = "ACGTA"
    mean, K = per_step(seq)
    q = ar1_steps(mean, K, 3000, 0.5, rng)
    t = np.arange(3000)[:, None]
    q[..., 5] += 20.0 * np.exp(-t / 150.0)
    q[..., 2] += 1.0 * np.exp(-t / 150.0)
    r = CoarseGrain(StepEnsemble(q, seq), 300.0, m_values=[1], n_boot=100).run().results
    assert r["discarded_frames"] >= 300
    b = r["by_m"][1]
    z = (b["mean"][:, [2, 5]] - mean[:, [2, 5]]) / b["mean_err"][:, [2, 5]]
    assert np.all(np.abs(z) < 3.5), z
    bc = CoarseGrain(StepEnsemble(q, seq), 300.0, m_values=[1], n_boot=100, discard=0).run().results["by_m"][1]
    zc = (bc["mean"][:, 5] - mean[:, 5]) / b["mean_err"][:, 5]   # bias / precision of the right analysis
    assert np.all(zc > 3), zc


def test_run_on_a_selection_of_frames_is_the_estimate_of_those_frames():
    """CoarseGrain goes through the analyses' one loop (mdbridge/geometry/analysis_base.py,
    the whole-trajectory kind): run(start, stop, step) estimates from exactly the ensemble
    of those frames (the truth: the ensemble cut to them); a control selection shifted by
    one frame gives another estimate."""
    rng = np.random.default_rng(5)
    seq = "ACGTA"
    mean, K = per_step(seq)
    q = ar1_steps(mean, K, 1200, 0.3, rng)
    t = 0.5 * np.arange(1200)
    kw = dict(temperature_K=300.0, m_values=[1], n_boot=20, discard=0)
    got = CoarseGrain(StepEnsemble(q, seq, times_ps=t), **kw).run(100, 1100, 2).results
    want = CoarseGrain(StepEnsemble(q[100:1100:2], seq, times_ps=t[100:1100:2]), **kw).run().results
    assert got.frames_used == want.frames_used == got.frames_total == 500 and got.dt_ps == want.dt_ps == 1.0
    for key in ("mean", "K", "K_err"):
        np.testing.assert_array_equal(got.by_m[1][key], want.by_m[1][key])
    shifted = CoarseGrain(StepEnsemble(q[101:1101:2], seq), **kw).run().results
    assert not np.array_equal(shifted.by_m[1]["K"], got.by_m[1]["K"])
