"""results/dispersion/errors/: the committed numbers come back from the committed inputs.

seeds.json is recomputed by the seed-differences step from the committed mode tables, tensions
and block errors; errors.json's summary is held to seeds.json and prediction.json; the old
chi^2 (fit errors, damped frequencies, no tension correction) is the invariance step's
committed one (results/dispersion/seed2/seeds.json)."""
import json
import math
from pathlib import Path

import pytest

from mdbridge.analysis.realisation_floor import between_realisation_floor

ROOT = Path(__file__).resolve().parents[2]
D = ROOT / "results/dispersion/errors"


@pytest.fixture(scope="module")
def recomputed(tmp_path_factory):
    from dnarod.steps.dispersion import seed_differences_step
    r = ROOT / "results/dispersion"
    out = tmp_path_factory.mktemp("errors") / "seeds.json"
    return seed_differences_step({"seed1": (r / "seed2/seed1_modes_1000_3000.json", D / "tension_seed1_1000_3000.json"),
                                  "seed2": (r / "seed2/modes_1000_3000.json", r / "seed2/tension.json")}, out,
                                 [D / f"blocks_{k}.json" for k in ("bend", "twist", "stretch")],
                                 r / "cg_provisional/params.json")


def _kinds(variant):
    return {k: (v["chi2"], v["dof"]) for k, v in variant["differences_by_kind"][0].items()}


def test_seeds_json_comes_back(recomputed):
    committed = json.loads((D / "seeds.json").read_text())
    for name, v in committed["variants"].items():
        for c in v:
            got, want = _kinds(recomputed["variants"][name][c]), _kinds(v[c])
            assert got.keys() == want.keys()
            for k in want:
                assert got[k][1] == want[k][1] and got[k][0] == pytest.approx(want[k][0], rel=1e-9), (name, c, k)


def test_summary_and_the_old_numbers():
    e = json.loads((D / "errors.json").read_text())
    s = json.loads((D / "seeds.json").read_text())
    old = json.loads((ROOT / "results/dispersion/seed2/seeds.json").read_text())["differences_by_kind"]["seed2"]
    c = e["chi2_by_kind"]
    for k in ("bend", "twist", "stretch"):
        assert c["old_fit_errors_damped_raw"][k]["chi2"] == pytest.approx(old[k]["chi2"], abs=0.01)
        assert c["old_fit_errors_damped_raw"][k]["dof"] == old[k]["dof"]
    new = s["variants"]["block_errors"]["tension_corrected"]["differences_by_kind"][0]
    for k, v in new.items():
        assert c["block_errors_tension_corrected"][k]["chi2"] == pytest.approx(v["chi2"], abs=0.01)
    # the calibration rule, here on the fraying full-charge vacuum seeds (open fraction 0.24, 0.27)
    assert 0.4 <= new["pooled"]["chi2"] / new["pooled"]["dof"] <= 1.9
    assert all(new[k]["chi2"] / new[k]["dof"] <= 3.5 and new[k]["dof"] >= 3 for k in ("bend", "twist", "stretch"))
    assert e["open_fraction"]["seeds_1000_3000_ps"] == {"seed1": 0.24, "seed2": 0.268}


def test_paper_rod_box_and_the_kicked_wave():
    e = json.loads((D / "errors.json").read_text())
    p = json.loads((D / "prediction.json").read_text())
    assert set(p["predictions"]) == {"paper_rod", "paper_rod_box"}
    committed = json.loads((ROOT / "results/dispersion/prediction.json").read_text())
    for a, b in zip(committed["rows"], p["rows"]):       # the paper row is unchanged
        assert a["paper_rod_omega_per_ps"] == b["paper_rod_omega_per_ps"]
    low = [r for r in e["paper_rod_box"]["rows"] if r["kind"] == "bend" and r["n"] <= 3]
    assert all(1.04 <= r["md_over_paper_rod"] <= 1.051 for r in low)        # the 4-5 % excess
    assert all(abs(r["md_over_paper_rod_box"] - 1) <= 0.015 for r in low)
    f = e["kicked_wave"]["floor_from_committed"]
    ref = between_realisation_floor([1.12, 1.32], [0.03, 0.06])
    assert f["tau"] == pytest.approx(ref["tau"]) and f["floor"] == pytest.approx(ref["tau_interval_68"][1])
    assert math.isclose(f["tau"], 0.133, abs_tol=1e-3)


def test_predict_step_writes_both_rows(tmp_path):
    """The predict step with --md-inertia reproduces errors/prediction.json's two rows."""
    from dnarod.steps.dispersion import predict_and_compare
    r = ROOT / "results/dispersion"
    got = predict_and_compare(r / "modes.json", tmp_path / "p.json", [r / "tension.json"], n_fit_max=4,
                              md_inertia=r / "cg_provisional/params.json")
    want = json.loads((D / "prediction.json").read_text())
    assert set(got["predictions"]) == {"paper_rod", "paper_rod_box"}
    for a, b in zip(got["rows"], want["rows"]):
        for k in ("paper_rod_omega_per_ps", "paper_rod_box_omega_per_ps"):
            assert a[k] == pytest.approx(b[k], rel=1e-9)
