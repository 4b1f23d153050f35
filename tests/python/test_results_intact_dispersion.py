"""The intact duplex's dispersion (results/dispersion/intact, written by
`python3 -m dnarod.steps.intact results/dispersion/intact --coarse-grain`; docs/intact.md,
"The intact duplex's dispersion").

- The contract other tools read: per seed modes.json, tension.json, mode_series.npz in the
  layout of results/dispersion/mode_series.npz covering at least 2500 ps after the discarded
  start, integrity.json with the open fraction after the discard, per pair and at the junction.
- The discard comes from the run's own relaxation and is at most 500 ps.
- Errors that cover realisations: the chi2 of the two seeds' tension-corrected differences
  with the block errors, over its degrees of freedom, pooled over bend, twist and stretch, lies
  within 0.4-1.9; no kind's is above 3.5; each kind has at least 3 degrees of freedom.
  Controls that must fail: the same differences with one record's fit errors, or without the
  tension correction, in at least one kind (the issue that started this found bend 70 for 9).
- prediction.json holds both rows of the paper's rod per mode: as published, and at the
  MD box's length with the atoms' rho and I.
"""
import json
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
INTACT = ROOT / "results" / "dispersion" / "intact"
SEEDS = ("seed1", "seed2")
KINDS = ("bend", "twist", "stretch")


def load(name):
    return json.loads((INTACT / name).read_text())


def test_the_discard_is_the_run_s_own_and_at_most_500_ps():
    d = load("discard.json")
    assert 0 < d["discard_ps"] <= 500 and d["discard_ps"] % 50 == 0
    assert d["discard_ps"] >= d["longest_start_ps"]
    assert set(d["per_seed"]) == set(SEEDS)
    for seed in SEEDS:
        assert load(f"{seed}/tension.json")["discard_ps"] == d["discard_ps"]


@pytest.mark.parametrize("seed", SEEDS)
def test_each_seed_s_contract(seed):
    d = INTACT / seed
    discard = load("discard.json")["discard_ps"]
    s = np.load(d / "mode_series.npz", allow_pickle=False)
    for key in ("r0_times_ps", "r0_bend", "r0_twist", "r0_stretch", "r0_open_fraction", "header"):
        assert key in s.files, key
    t = s["r0_times_ps"]
    assert s["r0_bend"].shape == (len(t), 14, 2, 2) and s["r0_twist"].shape == (len(t), 14, 2)
    assert s["r0_stretch"].shape[0] == len(t) and s["r0_open_fraction"].shape == (len(t),)
    assert t[-1] - max(t[0], discard) >= 2500.0
    m = load(f"{seed}/modes.json")
    assert m["n_bp"] == 158 and {e["kind"] for e in m["modes"]} == set(KINDS)
    tension = load(f"{seed}/tension.json")
    assert np.isfinite(tension["tension_pN"]) and tension["tension_err_pN"] > 0
    g = load(f"{seed}/integrity.json")
    assert g["junction_pairs"] == [156, 157, 0, 1]
    per_pair = np.array(g["open_fraction_per_pair"], float)
    assert per_pair.shape == (158,)
    assert g["open_fraction"] == pytest.approx(per_pair.mean(), abs=1e-9)
    assert g["junction_open_fraction"] == pytest.approx(per_pair[[156, 157, 0, 1]].mean(), abs=1e-9)
    assert g["open_fraction"] < 0.03             # the held duplex keeps at least 97 % of its pairs


def test_the_seeds_errors_cover_their_scatter():
    s = load("seeds.json")
    assert s["errors"] == "block_errors"
    by_kind = s["differences_by_kind"][0]
    for kind in KINDS:
        assert by_kind[kind]["dof"] >= 3, (kind, by_kind[kind])
        assert by_kind[kind]["chi2_per_dof"] <= 3.5, (kind, by_kind[kind])
    assert 0.4 <= by_kind["pooled"]["chi2_per_dof"] <= 1.9, by_kind["pooled"]
    assert by_kind["pooled"]["dof"] == sum(by_kind[k]["dof"] for k in KINDS)


def test_control_fit_errors_or_no_tension_correction_fail():
    """The same check with one record's fit errors, or without the tension correction, must
    fail: otherwise it could not tell the block errors from any other."""
    v = load("seeds.json")["variants"]

    def fails(by_kind):
        return (any(by_kind[k]["chi2_per_dof"] > 3.5 for k in KINDS if k in by_kind)
                or not 0.4 <= by_kind["pooled"]["chi2_per_dof"] <= 1.9)
    assert fails(v["fit_errors"]["tension_corrected"]["differences_by_kind"][0])
    assert fails(v["block_errors"]["raw"]["differences_by_kind"][0])


def test_prediction_has_both_rods_per_mode():
    p = load("prediction.json")
    assert {"paper_rod", "paper_rod_box"} <= set(p["predictions"])
    for seed in SEEDS:
        q = load(f"{seed}/prediction.json")
        rows = [r for r in q["rows"] if r.get("md_omega0_per_ps") is not None]
        assert rows and all("z_paper_rod" in r and "z_paper_rod_box" in r for r in rows)
