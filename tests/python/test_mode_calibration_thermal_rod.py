"""The errors of `dnarod modes` on thermal-rod series, against linear theory
(bench/mode_spectrum_calibration.py --thermal-rod; docs/analysis.md, "Calibration").

The series: Langevin runs of the paper's 158-bp rod at 0.03 K, damped modes of Q ~ 1.5-30,
each through the command's own code path (the rod file read as `dnarod modes` reads it,
mode_table). The truth: the linearised damped operator (LinearRod.damped_modes, itself
checked against closed forms and a hand-built block in test_rod_linear.py).

* the committed table (30 realisations): every damped mode's stated / RMS error of omega
  is within 0.7-1.4 except the cases named in OUTSIDE (a result, stated in the docs), and
  the control (each mode a sinusoid in white noise) is outside the band in every case;
  the overdamped bend n = 1 is refused in OVERDAMPED_REFUSED of them; the truth in the table
  is the scene's linear theory now; no passed fit lies more than 25 % off the truth (the
  wrong peaks that the second background's floor removed, docs/analysis.md);
* one new realisation (a seed not in the table), run here: the median |z| of its modes
  about the truth, z = (omega - truth) / stated error, is that of a standard normal
  (0.674, within 3 of its sampling errors for the number of modes); the control's is far
  above it. The median, not the RMS: one mode fitted on the wrong peak (see OUTSIDE) must
  not decide.
Cost: ~40 s of one core (one rod run and its mode table).
"""
from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from benchscripts import load_bench

ROOT = Path(__file__).resolve().parents[2]
CAL = load_bench("mode_spectrum_calibration.py")
TABLE = ROOT / "bench" / "results" / "mode_spectrum_calibration_thermal_rod.json"
REALISATIONS = ROOT / "bench" / "results" / "mode_spectrum_calibration_thermal_rod_realisations.json"
# kind n whose stated / RMS lies outside 0.7-1.4 in the committed table (docs/analysis.md,
# "Thermal-rod series"): twist 9, whose errors are ~45 % too large (1.45)
OUTSIDE = {"twist 9"}
# the overdamped bend n = 1 is refused in this many of the 30 realisations (reported as an
# oscillation of Q ~ 1 in the others: docs/analysis.md)
OVERDAMPED_REFUSED = 16
NEW_SEED = 1001


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


def test_a_new_realisation_scatters_as_its_errors_say(tmp_path):
    truth = CAL.thermal_rod_truth()
    rows = CAL.thermal_rod_realisation(NEW_SEED, tmp_path)
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
    fits did, docs/analysis.md), and the ratio over the fits is the table's: twist 9 alone
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
