"""The bend frequencies against the tension (mdbridge/analysis/tension_series.py), against
things true independently of it: an exact line, sampling theory of a straight-line fit with
errors in both coordinates (z of the slope a standard normal over many synthetic data sets;
the control that ignores the tension's error is overconfident), the mass scaling of the
linear rod's slope, and runs synthesised from a rod of known mass (the control: the same
runs against a rod of twice the mass are rejected). ~5 s."""
import json
import math
import subprocess
import sys

import numpy as np
import pytest

from dna_models.errors import InputError
from mdbridge.analysis.dispersion_prediction import Duplex, bend_frequencies, paper_material
from mdbridge.analysis.tension_series import frequency_against_tension, line_with_errors, predicted_slope
from mdbridge.rod.linear import UniformMaterial

DUPLEX = Duplex(158, 15, 300.0)


def heavier(mat: UniformMaterial, f: float) -> UniformMaterial:
    return UniformMaterial(K=mat.K, I=np.asarray(mat.I) * f, rho=mat.rho * f, Gamma0=mat.Gamma0, Omega0=mat.Omega0)


def test_exact_line_and_bad_input():
    x = np.array([10.0, 20.0, 40.0, 70.0])
    fit = line_with_errors(x, 0.1 * np.ones(4), 3.0 + 0.5 * x, 0.2 * np.ones(4))
    assert fit["slope"] == pytest.approx(0.5, rel=1e-8) and fit["intercept"] == pytest.approx(3.0, rel=1e-8)
    assert fit["chi2"] == pytest.approx(0.0, abs=1e-12) and fit["dof"] == 2
    # a slope whose chi^2 + 1 interval crosses zero: with negligible x errors it is ordinary
    # weighted least squares, error sigma / sqrt(S_xx) = 0.3 / sqrt(5) on both sides
    f = line_with_errors([0, 1, 2, 3], [1e-6] * 4, [0.1, -0.2, 0.4, 0.1], [0.3] * 4)
    assert f["slope_err_interval"][0] < 0 < f["slope"]
    e = 0.3 / 5 ** 0.5
    assert f["slope_err_interval"] == pytest.approx([f["slope"] - e, f["slope"] + e], rel=1e-5)
    with pytest.raises(InputError, match="same tension"):
        line_with_errors([5.0, 5.0], [1, 1], [1.0, 2.0], [1, 1])
    with pytest.raises(InputError, match="at least 2"):
        line_with_errors([5.0], [1], [1.0], [1])


def test_slope_errors_match_the_scatter_and_ignoring_x_errors_does_not():
    """2000 data sets of 4 points, errors in T comparable to those in y / slope: the
    slope's z about the truth has mean 0 and s.d. 1 (+- 5 sampling errors); the control, the
    same fit with the T errors dropped, states errors far too small (s.d. of z > 1.3)."""
    rng = np.random.default_rng(3)
    x0 = np.array([20.0, 40.0, 45.0, 70.0])
    ex, ey, s0 = np.array([3.0, 3.0, 4.0, 5.0]), np.array([0.5, 0.5, 0.6, 0.8]), 0.4
    z, zc = [], []
    for _ in range(2000):
        x = x0 + rng.normal(size=4) * ex
        y = 1.0 + s0 * x0 + rng.normal(size=4) * ey
        f = line_with_errors(x, ex, y, ey)
        z.append((f["slope"] - s0) / f["slope_err"])
        c = line_with_errors(x, np.zeros(4), y, ey)
        zc.append((c["slope"] - s0) / c["slope_err"])
    z, zc = np.array(z), np.array(zc)
    n = len(z)
    assert abs(np.median(z)) < 5 / math.sqrt(n) * 1.25
    assert abs(np.std(z) - 1) < 5 / math.sqrt(2 * n) + 0.05     # (the slope's error is itself estimated)
    assert np.std(zc) > 1.3


def test_rod_slope_scales_with_the_mass():
    """omega^2 of a rod with every inertia (rho and I) times f is omega^2 / f at every T, so
    the slope is too; at n = 1 it is close to the string's k^2 / mu (below it: the tension
    also strains the shear, module doc)."""
    mat = paper_material(DUPLEX)
    s1 = predicted_slope(mat, DUPLEX, 40.0, [1, 2, 3, 4])
    s2 = predicted_slope(heavier(mat, 2.0), DUPLEX, 40.0, [1, 2, 3, 4])
    assert s1 / s2 == pytest.approx(np.full(4, 2.0), rel=1e-6)
    from dna_models.units import Units
    u = Units.paper()
    k = 2 * np.pi / (158 * u.rise_A * 1e-10)
    string = k ** 2 / u.rho * 1e-24 * 1e-12         # (rad/s)^2 / N -> (rad/ps)^2 / pN
    assert 0.85 < s1[0] / string < 1.0


def test_runs_from_a_rod_of_known_mass_give_its_slope_and_a_heavier_rod_is_rejected():
    """Four runs at 22-80 pN synthesised from the paper's rod (frequencies with 1.5 %
    errors, tensions with 3 pN), noise added: the measured slope agrees with the rod's
    (|z| < 3 at every n over 50 data sets, mean |z| that of a normal); against a rod of twice
    the mass (the control) it does not."""
    mat = paper_material(DUPLEX)
    ns = [1, 2, 3]
    T_true = [22.0, 40.0, 55.0, 80.0]
    rng = np.random.default_rng(11)
    z, zc = [], []
    for _ in range(50):
        runs = []
        for i, T in enumerate(T_true):
            w = bend_frequencies(mat, DUPLEX, T, ns)
            runs.append({"name": f"r{i}", "tension_pN": T + 3.0 * rng.normal(), "tension_err_pN": 3.0,
                         "omega0": {n: (float(wn * (1 + 0.015 * rng.normal())), float(0.015 * wn))
                                    for n, wn in zip(ns, w)}})
        rows = frequency_against_tension(runs, mat, DUPLEX, ns)
        assert all(r["reason"] is None and r["runs"] == ["r0", "r1", "r2", "r3"] for r in rows)
        z += [r["z"] for r in rows]
        zc += [frequency_against_tension(runs, heavier(mat, 2.0), DUPLEX, ns)[0]["z"]]
    z = np.abs(np.array(z))
    assert z.max() < 4 and abs(z.mean() - math.sqrt(2 / math.pi)) < 0.2, z
    assert np.min(zc) > 3, zc


def test_too_few_runs_are_refused_with_the_reason():
    mat = paper_material(DUPLEX)
    runs = [{"name": "a", "tension_pN": 20.0, "tension_err_pN": 2.0, "omega0": {1: (0.013, 0.0002)}},
            {"name": "b", "tension_pN": 40.0, "tension_err_pN": 2.0, "omega0": {1: (0.015, 0.0002), 2: (None, None)}}]
    (row,) = frequency_against_tension(runs, mat, DUPLEX, [1])
    assert "2 runs measure bend n = 1" in row["reason"]


def _prediction(path, T, omegas, n_bp=158):
    """A predict-step record with what the series reads: tension, bend rows, the dynamics fit."""
    rows = [{"kind": "bend", "n": n, "md_omega0_per_ps": w, "md_omega0_err_per_ps": 0.01 * w}
            for n, w in omegas.items()]
    path.write_text(json.dumps({"n_bp": n_bp, "turns": 15, "temperature_K": 300.0, "length_A": 534.0,
                                "tension": {"tension_pN": T, "tension_err_pN": 2.0}, "rows": rows,
                                "fit": {"dynamics": {"tension_pN": T + 1.0, "tension_err_pN": 1.0}}}))
    return path


def test_the_series_step_end_to_end_and_its_input_errors(tmp_path):
    """`python -m dnarod.steps.dispersion series` on three runs of the paper's rod (exact
    frequencies): the slope is the rod's (z ~ 0); a run of another duplex is refused with
    exit 2, naming the file, and nothing is written."""
    mat = paper_material(DUPLEX)
    paths = []
    for T in (20.0, 40.0, 60.0):
        w = bend_frequencies(mat, DUPLEX, T, [1, 2])
        paths.append(_prediction(tmp_path / f"p{int(T)}.json", T, {1: float(w[0]), 2: float(w[1])}))
    out = tmp_path / "series.json"
    args = [sys.executable, "-m", "dnarod.steps.dispersion", "series", *[f"r{i}={p}" for i, p in enumerate(paths)],
            "-o", str(out), "--n", "1", "2"]
    r = subprocess.run(args, capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    rec = json.loads(out.read_text())
    assert [m["n"] for m in rec["modes"]] == [1, 2]
    for m in rec["modes"]:
        assert m["reason"] is None and abs(m["z"]) < 0.5 and m["slope_over_predicted"] == pytest.approx(1, abs=0.03)
    assert rec["runs"][1]["omega0_per_ps"]["1"][0] == pytest.approx(bend_frequencies(mat, DUPLEX, 40.0, [1])[0])
    bad = _prediction(tmp_path / "other.json", 30.0, {1: 0.01}, n_bp=21)
    out2 = tmp_path / "series2.json"
    r = subprocess.run([*args[:4], f"a={paths[0]}", f"b={bad}", "-o", str(out2)], capture_output=True, text=True,
                       timeout=120)
    assert r.returncode == 2 and "other.json" in r.stderr and "one duplex" in r.stderr, r.stderr
    assert not out2.exists()
