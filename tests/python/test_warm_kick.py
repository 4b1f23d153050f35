"""The kicked comparison at 300 K (bench/warm_kick.py; docs/results.md, "The kicked comparison
at 300 K"): box-held 158-bp rods equilibrated at 300 K in a box that holds the MD's tension,
kicked as the MD was, through the MD's wave analysis.

* the machinery at 0 K, where the answer is known independently: the straight rod in its built
  box, kicked by bench/warm_kick.py's Python kick and run by its NVE scene, must give the
  paper rod's standing mode as the `dna_planar` kind makes and `paper-figures` measures it
  (docs/figures/wavespeed.json; 1.674 A/ps). Control: the same lab velocity written into the
  body frame without the directors (a helical kick) leaves the fundamental nearly unkicked;
* the box: `box_for_tension` at the mean-field slack tension gives back the built box;
* two short warm runs: fixed seeds reproduce bit for bit, different seeds differ, and the run
  reports its tension, speed and amplitude;
* the committed ensemble (results/warm_kick/) holds the numbers docs/results.md quotes.
"""
import json
import math
from pathlib import Path

import numpy as np
import pytest
from benchscripts import load_bench

from mdbridge.rod.slack import box_for_tension, slack_tension

WK = load_bench("warm_kick.py")
ROOT = Path(__file__).resolve().parents[2]


def test_the_kick_at_zero_temperature_is_the_paper_rods_mode(tmp_path, monkeypatch):
    ref = json.loads((ROOT / "docs/figures/wavespeed.json").read_text())
    mat = WK.material("paper")
    rest = WK.straight(1.0)
    r = WK.kicked(mat, rest, 1.0, 600.0, tmp_path, seed=0, temperature_K=0.0)
    assert r["reason"] is None
    assert r["wave_kind"] == "standing"
    # the kind's run is DOP853 at rtol 1e-9, this one RK4 at 20 steps per ps: agreement to the
    # fit's error plus 1e-3 relative
    tol = 3 * math.hypot(ref["measured_err_A_per_ps"], r["speed_err_A_per_ps"]) + 1e-3 * ref["measured_A_per_ps"]
    assert abs(r["speed_A_per_ps"] - ref["measured_A_per_ps"]) < tol, (r["speed_A_per_ps"], ref)
    assert r["box_length_A"] == pytest.approx(158 * 3.38, rel=1e-9)
    # the kick in the lab, read back through the directors of the NVE run's own frame
    R, box = WK.lab_frame(mat, rest)
    kicked, e_kick = WK.add_kick(rest, R, box, 1.0)
    v = np.einsum("ijk,ik->ij", R, kicked["gamma"]) * WK.U.velocity_A_per_ps
    s = np.arange(158) / 158
    np.testing.assert_allclose(v, np.sin(2 * np.pi * s)[:, None] * e_kick, atol=1e-12)
    assert abs(e_kick @ box) < 1e-12 * np.linalg.norm(box)
    # control: the lab velocity put into the body frame as it is (no R^T): the kick follows the
    # helix and the fundamental gets almost none of it
    wrong = {k: np.array(x) for k, x in rest.items()}
    wrong["gamma"] += np.sin(2 * np.pi * s)[:, None] * e_kick / WK.U.velocity_A_per_ps
    monkeypatch.setattr(WK, "add_kick", lambda state, R_, box_, A: (wrong, e_kick))
    bad = WK.kicked(mat, rest, 1.0, 600.0, tmp_path, seed=0, temperature_K=0.0)
    assert bad["mode_amplitude_A"] < 0.2 * r["mode_amplitude_A"], (bad["mode_amplitude_A"], r["mode_amplitude_A"])


def test_the_box_for_the_slack_tension_is_the_built_box():
    u = WK.U
    L, kT = WK.L, u.kT_to_rod(300.0)
    F = slack_tension(L, 158, kT, u.D_star[0], 1.0, u.C_star[2], samples=2000).mean_field
    assert box_for_tension(F, L, 158, kT, u.D_star[0], 1.0, u.C_star[2]) == pytest.approx(1.0, abs=1e-12)
    # less tension, a shorter box; more, a longer one (a stiff rod's X / L follows F / C3)
    lo = box_for_tension(0.5 * F, L, 158, kT, u.D_star[0], 1.0, u.C_star[2])
    hi = box_for_tension(2.0 * F, L, 158, kT, u.D_star[0], 1.0, u.C_star[2])
    assert lo < 1.0 < hi


def test_two_short_warm_runs(tmp_path):
    args = dict(tension_pN=5.0, seed0=1, t_eq=60.0, run_ps=200.0, friction=0.01, A_v=1.0,
                workdir=tmp_path, log=lambda *a: None)
    e = WK.ensemble("paper", runs=2, **args)
    runs = e["runs"]
    assert [r["seed"] for r in runs] == [1, 2]
    assert e["Gamma03"] == pytest.approx(0.965, abs=0.002)     # 5 pN: 3.5 % of slack left in the box
    for r in runs:
        assert math.isfinite(r["equilibrium_tension_pN"]) and math.isfinite(r["mode_amplitude_A"])
        assert r["box_length_A"] == pytest.approx(e["box_length_A"], rel=1e-5)   # the box is kept
    assert runs[0]["mode_amplitude_A"] != runs[1]["mode_amplitude_A"]           # seeds differ
    again = WK.ensemble("paper", runs=1, **dict(args, seed0=2))["runs"][0]
    assert again["mode_amplitude_A"] == runs[1]["mode_amplitude_A"]              # a seed repeats
    assert again["equilibrium_tension_pN"] == runs[1]["equilibrium_tension_pN"]
    assert e["summary"]["mode_amplitude_A"]["n"] == 2
