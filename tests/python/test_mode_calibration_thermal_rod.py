"""The errors of `dnarod modes` on thermal-rod series, against linear theory
(bench/mode_spectrum_calibration.py --thermal-rod; docs/modes.md, "How it is verified").

The series: Langevin runs of the paper's 158-bp rod at 0.03 K, damped modes of Q ~ 1.5-30,
each through the command's own code path (the rod file read as `dnarod modes` reads it,
mode_table). The truth: the linearised damped operator (LinearRod.damped_modes, itself
checked against closed forms and a hand-built block in test_rod_linear.py).

* the committed table (30 realisations): every damped mode's stated / RMS error of omega
  is within 0.7-1.4 except the cases named in OUTSIDE (a result, stated in the docs), and
  the control (each mode a sinusoid in white noise) is outside the band in every case;
  the overdamped bend n = 1 is refused in OVERDAMPED_REFUSED of them; the truth in the table
  is the scene's linear theory now; no passed fit lies more than 25 % off the truth (the
  wrong peaks that the second background's floor removed, docs/modes.md);
* one new realisation (a seed not in the table), run here: the median |z| of its modes
  about the truth, z = (omega - truth) / stated error, is that of a standard normal
  (0.674, within 3 of its sampling errors for the number of modes); the control's is far
  above it. The median, not the RMS: one mode fitted on the wrong peak (see OUTSIDE) must
  not decide.
* kinetic equipartition (dispersion_prediction.axial_inertia): every twist and stretch
  mode's inertia comes back as the scene's I3 and rho, its mean over the realisations
  within 3 standard errors and its stated error / RMS within 0.7-1.4; the control (the
  damped frequency in place of omega0) fails on the low-Q modes; in the new realisation
  the median |z| about the truth is a standard normal's, and that of the control (the
  variance of one real series taken as <|c_n|^2>, half of it) is far above.
Cost: ~40 s of one core (one rod run and its mode table).
"""
from __future__ import annotations

import json
import math
import re
from pathlib import Path

import numpy as np
import pytest

from benchscripts import load_bench

ROOT = Path(__file__).resolve().parents[2]
CAL = load_bench("mode_spectrum_calibration.py")
TABLE = ROOT / "bench" / "results" / "mode_spectrum_calibration_thermal_rod.json"
REALISATIONS = ROOT / "bench" / "results" / "mode_spectrum_calibration_thermal_rod_realisations.json"
# kind n whose stated / RMS lies outside 0.7-1.4 in the committed table (docs/modes.md,
# "The thermal rod against linear theory"): twist 9, whose errors are ~45 % too large (1.45)
OUTSIDE = {"twist 9"}
# the overdamped bend n = 1 is refused in this many of the 30 realisations (reported as an
# oscillation of Q ~ 1 in the others: docs/modes.md)
OVERDAMPED_REFUSED = 17
NEW_SEED = 1001
# axial modes whose kinetic inertia fails its calibration in the committed table
# (docs/modes.md, "Kinetic equipartition on the same series"): stated / RMS 1.46
# (conservative) and 0.67
INERTIA_OUTSIDE = {"stretch 1", "stretch 11"}


@pytest.fixture(scope="module")
def table():
    return json.loads(TABLE.read_text())


def test_committed_table_is_calibrated_and_its_control_fails(table):
    lo, hi = table["pass_band"]
    assert (lo, hi) == (0.7, 1.4) and table["realisations"] >= 30
    damped = [c for c in table["cases"] if not c["overdamped"]]
    assert len(damped) == 3 * 14 - 1
    for c in damped:
        key = f"{c['kind']} {c['n']}"
        r = c["fit"]["omega_ratio"]
        assert (key in OUTSIDE) == (r is None or not lo <= r <= hi), (key, r, c["fit"]["omega_ratio_68"])
        assert c["control"]["omega_ratio"] is None or not lo <= c["control"]["omega_ratio"] <= hi, (key, c["control"])
    (over,) = [c for c in table["cases"] if c["overdamped"]]
    assert (over["kind"], over["n"]) == ("bend", 1) and len(over["refused"]) == OVERDAMPED_REFUSED


def test_committed_truth_is_the_scenes_linear_theory(table):
    truth = CAL.thermal_rod_truth()
    assert table["scene"]["thermal"]["friction_translational"] == list(CAL.ROD_FRICTION_TRANSLATIONAL)
    for c in table["cases"]:
        if not c["overdamped"]:
            w, g = truth[(c["kind"], c["n"])]
            assert c["fit"]["omega_true_per_ps"] == pytest.approx(w, rel=1e-9)
            assert c["fit"]["gamma_true_per_ps"] == pytest.approx(g, rel=1e-9)


def test_committed_inertia_is_the_scenes_and_its_control_fails(table):
    inertia = CAL.thermal_rod_inertia_truth()
    assert inertia == {"twist": 2.0, "stretch": 1.0}
    cases = [c for c in table["cases"] if c["kind"] != "bend"]
    assert all("inertia" in c for c in cases)
    for c in cases:
        i = c["inertia"]
        assert i["truth_rod_units"] == inertia[c["kind"]]
        assert i["fitted"] >= 27, (c["kind"], c["n"], i["fitted"])
        assert i["pass"] == (f"{c['kind']} {c['n']}" not in INERTIA_OUTSIDE), (c["kind"], c["n"], i)
    assert set(table["inertia_failing"]) == INERTIA_OUTSIDE
    # the control (omega for omega0) is rejected by its mean where the damping matters (Q 2)
    ctl = next(c["inertia"]["control"] for c in cases if (c["kind"], c["n"]) == ("stretch", 1))
    assert ctl["z"] < -3 and not ctl["pass"]
    # the docs' summary (docs/modes.md)
    doc = re.sub(r"\s+", " ", (ROOT / "docs" / "modes.md").read_text())
    mean = {k: [c["inertia"]["mean"] for c in cases if c["kind"] == k and c["n"] >= 2] for k in ("twist", "stretch")}
    tw, st = np.array(mean["twist"]), np.array(mean["stretch"])
    assert f"twist n = 2-14 give {tw.min():.3f}-{tw.max():.3f} of the truth" in doc
    assert f"(mean over n {tw.mean():.3f} +- {tw.std(ddof=1) / math.sqrt(len(tw)):.3f})" in doc
    assert f"(n = 2-14 {st.mean():.3f} +- {st.std(ddof=1) / math.sqrt(len(st)):.3f}:" in doc
    assert f"stretch n = 1 (Q 2: {ctl['z']:.1f} standard errors)" in doc


def _inertia_z(rows, scale=1.0):
    """z of each passed axial mode's kinetic inertia about the scene's (the oscillator
    variance multiplied by `scale`: 0.5 is the control)."""
    from mdbridge.analysis.dispersion_prediction import axial_inertia
    truth = CAL.thermal_rod_inertia_truth()
    z = []
    for key, r in rows.items():
        kind, n = key.split()
        if kind == "bend" or r["reason"] is not None or not r["oscillator_variance"]:
            continue
        entry = {"kind": kind, "n": int(n), "omega_per_ps": r["omega"], "omega_err_per_ps": r["omega_err"],
                 "damping_per_ps": r["gamma"], "damping_err_per_ps": r["gamma_err"],
                 "oscillator_variance": scale * r["oscillator_variance"],
                 "oscillator_variance_err": scale * r["oscillator_variance_err"]}
        v, e = axial_inertia(entry, CAL.ROD_BP, r["length_A"], CAL.ROD_TEMPERATURE_K)
        z.append((v - truth[kind]) / e)
    return z


def test_a_new_realisation_scatters_as_its_errors_say(tmp_path):
    truth = CAL.thermal_rod_truth()
    rows = CAL.thermal_rod_realisation(NEW_SEED, tmp_path)
    # kinetic inertia of the axial modes, and its control (half the variance)
    zi, zic = _inertia_z(rows), _inertia_z(rows, 0.5)
    assert len(zi) >= 24, len(zi)
    sigma = 1 / (2 * 0.636 * math.sqrt(len(zi)))
    assert abs(np.median(np.abs(zi)) - 0.674) < 3 * sigma, sorted(np.abs(zi))
    assert np.median(np.abs(zic)) > 0.674 + 6 * sigma, sorted(np.abs(zic))
    z, zc = [], []
    for key, r in rows.items():
        kind, n = key.split()
        if (kind, int(n)) not in truth:                   # overdamped (bend n = 1)
            continue
        w = truth[(kind, int(n))][0]
        if r["reason"] is None:
            z.append((r["omega"] - w) / r["omega_err"])
        if r["control_reason"] is None:
            zc.append((r["control_omega"] - w) / r["control_omega_err"])
    assert len(z) >= 35, len(z)
    # median |z| of N standard normals: 0.674 +- 1 / (2 f sqrt(N)), f = 2 phi(0.674) = 0.636
    sigma = 1 / (2 * 0.636 * math.sqrt(len(z)))
    assert abs(np.median(np.abs(z)) - 0.674) < 3 * sigma, sorted(np.abs(z))
    assert np.median(np.abs(zc)) > 0.674 + 6 * sigma, sorted(np.abs(zc))      # control


def test_no_passed_fit_is_on_a_wrong_peak(table):
    """From each realisation's committed numbers: no fit that the command passed lies more
    than 25 % from the truth (before the second background's floor, 20 twist and stretch
    fits did, docs/modes.md), and the ratio over the fits is the table's: twist 9 alone
    outside the band."""
    rows = json.loads(REALISATIONS.read_text())
    assert len(rows) == table["realisations"]
    wrong = 0
    for c in table["cases"]:
        if c["overdamped"]:
            continue
        key, w = f"{c['kind']} {c['n']}", c["fit"]["omega_true_per_ps"]
        fits = [r[key] for r in rows.values() if r[key]["reason"] is None]
        kept = [f for f in fits if abs(f["omega"] / w - 1) <= 0.25]
        wrong += len(fits) - len(kept)
        if c["kind"] == "bend":
            assert len(kept) == len(fits), key
        err = np.array([f["omega_err"] for f in kept])
        dev = np.array([f["omega"] - w for f in kept])
        ratio = math.sqrt(np.mean(err ** 2) / np.mean(dev ** 2))
        assert (key == "twist 9") == (not 0.7 <= ratio <= 1.4), (key, ratio)
    assert wrong == 0
