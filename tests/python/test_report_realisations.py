"""The kicked MD's error between realisations (workflows/report/realisations.py) against its
independent truth, the committed realisations of the main job's setting
(results/main_job_realisations.json: 1.12 +- 0.03, 1.32 +- 0.06, 1.39 +- 0.08 A/ps).

* the record: its summary is what realisation_floor.py makes of its realisations, and it holds
  the committed main-job records' realisations;
* calibration: with a single run's error sqrt(err^2 + floor^2) the realisations' chi2 / dof
  lies in the central 95 % of chi2(dof) / dof ([0.025, 3.69] for 2 dof); the control, each
  run's own error (what the report printed before), lies far above it (16.3 / 2);
* prediction, left out: each realisation against the other two, with the floor from those two
  alone, within 1.5 errors; the control, the one-record errors, puts every one beyond 2.5;
* the report: a run of the main job's setting with one seed states the floor and says so; a
  run of another setting states one record's error and says that; several seeds take their
  own scatter."""
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
import yaml
from scipy.stats import chi2

from dnarod.configuration import validate
from dnarod.report import realisations as R
from mdbridge.analysis.realisation_floor import between_realisation_floor

ROOT = Path(__file__).resolve().parents[2]
REC = json.loads(R.RECORD.read_text())
X = np.array([r["speed_A_per_ps"] for r in REC["realisations"]])
S = np.array([r["speed_err_A_per_ps"] for r in REC["realisations"]])
BAND = 0.95


def _band(dof: int) -> tuple[float, float]:
    lo, hi = chi2.ppf([(1 - BAND) / 2, (1 + BAND) / 2], dof) / dof
    return float(lo), float(hi)


def _config(name: str) -> dict:
    return validate(yaml.safe_load((ROOT / "workflows/config" / name).read_text()), name)


def test_the_record_is_its_realisations():
    assert REC["summary"] == pytest.approx(R.summary(REC["realisations"]))
    assert REC["setting"] == R.setting(_config("default.yaml"))
    listed = {(r["date"], r["speed_A_per_ps"], r["speed_err_A_per_ps"]) for r in REC["realisations"]}
    for name in ("main_job", "main_job_1000ps"):
        mj = json.loads((ROOT / "results" / f"{name}.json").read_text())
        assert (mj["date"], mj["md_phase_speed_A_per_ps"], mj["md_phase_speed_err_A_per_ps"]) in listed, name
    assert len(X) == REC["summary"]["k"] >= 3


def test_the_floor_covers_the_realisations_and_one_record_does_not():
    s = REC["summary"]
    lo, hi = _band(s["dof"])
    with_floor = R.chi2_about_mean(X, np.hypot(S, s["floor_A_per_ps"])) / s["dof"]
    one_record = R.chi2_about_mean(X, S) / s["dof"]
    assert lo <= with_floor <= hi, (with_floor, lo, hi)
    assert one_record > 2 * hi, one_record                        # the control
    assert with_floor == pytest.approx(s["chi2_with_floor"] / s["dof"])
    assert one_record == pytest.approx(s["chi2_one_record"] / s["dof"])


def test_each_realisation_is_predicted_by_the_others():
    z_floor, z_one = [], []
    for i in range(len(X)):
        o = [j for j in range(len(X)) if j != i]
        f = between_realisation_floor(X[o], S[o])
        e = np.array(f["errors_with_floor"])
        mean, mean_err = np.sum(X[o] / e ** 2) / np.sum(e ** -2), np.sum(e ** -2) ** -0.5
        z_floor.append((X[i] - mean) / math.hypot(math.hypot(S[i], f["floor"]), mean_err))
        z_one.append((X[i] - f["mean"]) / math.hypot(S[i], f["mean_err"]))
    assert max(abs(z) for z in z_floor) < 1.5, z_floor
    assert min(abs(z) for z in z_one) > 2.5, z_one                # the control


def test_which_runs_get_the_floor():
    got = R.floor_for(_config("default.yaml"), 1)
    assert got["floor_A_per_ps"] == REC["summary"]["floor_A_per_ps"] and got["k"] == len(X)
    tiny = R.floor_for(_config("tiny.yaml"), 1)
    assert tiny["floor_A_per_ps"] is None and "not measured" in tiny["reason"]
    two = R.floor_for(_config("default.yaml"), 2)
    assert two["floor_A_per_ps"] is None and two["n_seeds"] == 2
    longer = _config("default.yaml")
    longer["md"]["run_ps"] = 1200                                 # another setting: no floor
    assert R.floor_for(longer, 1)["floor_A_per_ps"] is None
    assert R.floor_for(_config("default.yaml"), 1, ROOT / "results" / "no_such.json")["floor_A_per_ps"] is None


def test_record_appends_a_new_realisation_once(tmp_path):
    path = tmp_path / "realisations.json"
    path.write_text(R.RECORD.read_text())
    new = {"date": "2026-12-07", "machine": "test", "md_phase_speed_A_per_ps": 1.25,
           "md_phase_speed_err_A_per_ps": 0.05}
    assert R.record(path, new) is True
    assert R.record(path, new) is False                            # the same record twice: once
    got = json.loads(path.read_text())
    assert len(got["realisations"]) == len(X) + 1
    assert got["summary"] == pytest.approx(R.summary(got["realisations"])) and got["summary"]["k"] == len(X) + 1


def _quotes(rec: dict) -> list[tuple[str, str]]:
    """(page, text): the realisations' figures as docs/dispersion.md and docs/results.md print them."""
    s, reals = rec["summary"], rec["realisations"]
    rod = json.loads((ROOT / "docs/figures/wavespeed.json").read_text())
    first = reals[0]
    z = (rod["measured_A_per_ps"] - first["speed_A_per_ps"]) / math.hypot(
        math.hypot(first["speed_err_A_per_ps"], s["floor_A_per_ps"]), rod["measured_err_A_per_ps"])
    lo, hi = s["tau_interval_68_A_per_ps"]
    return ([("docs/dispersion.md", f"has {s['k']} realisations"),
             ("docs/dispersion.md", f"their chi2 is {s['chi2_one_record']:.1f} for {s['dof']} dof"),
             ("docs/dispersion.md", f"tau = {s['tau_A_per_ps']:.2f} A/ps, with a 68 % interval of "
                                    f"{lo:.2f}-{hi:.2f} A/ps"),
             ("docs/dispersion.md", f"the interval's upper end, {s['floor_A_per_ps']:.2f} A/ps"),
             ("docs/dispersion.md", f"sqrt(err^2 + {s['floor_A_per_ps']:.2f}^2) (chi2 {s['chi2_with_floor']:.2f} for "
                                    f"{s['dof']} dof)"),
             ("docs/results.md", f"{s['min_A_per_ps']:.2f}-{s['max_A_per_ps']:.2f} A/ps in {s['k']} runs"),
             ("docs/results.md", f"a floor of {s['floor_A_per_ps']:.2f} A/ps"),
             ("docs/results.md", f"a third {reals[2]['speed_A_per_ps']:.2f} +- {reals[2]['speed_err_A_per_ps']:.2f}"),
             ("docs/results.md", f"(z {z:.1f} for {first['speed_A_per_ps']:.2f})")]
            + [("docs/dispersion.md", f"{r['speed_A_per_ps']:.2f} +- {r['speed_err_A_per_ps']:.2f}") for r in reals])


def _unquoted(rec: dict) -> list[tuple[str, str]]:
    pages = {p: re.sub(r"\s+", " ", (ROOT / p).read_text()) for p in ("docs/dispersion.md", "docs/results.md")}
    return [(p, t) for p, t in _quotes(rec) if t not in pages[p]]


def test_docs_quote_the_realisations():
    """docs/dispersion.md ("The kicked wave") and docs/results.md ("The rod against the MD") quote
    results/main_job_realisations.json. Control: one more realisation changes what they must say."""
    assert _unquoted(REC) == []
    more = dict(REC, realisations=REC["realisations"] + [{"speed_A_per_ps": 1.5, "speed_err_A_per_ps": 0.05}])
    more["summary"] = R.summary(more["realisations"])
    assert len(_unquoted(more)) >= 5
