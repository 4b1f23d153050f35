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
import re
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


RESULT_FILES = ["results/warm_kick/cold.json", "results/warm_kick/warm_kick_5pN.json",
                "results/warm_kick/warm_kick_38pN.json"]


def test_the_committed_ensembles_are_what_the_docs_quote():
    """The ensembles as the docs describe them (20 runs per material, seeds 1-20, the paper's
    kick, 600 ps) and docs/results.md's table rendered from them by `--table`."""
    for name in RESULT_FILES[1:]:
        d = json.loads((ROOT / name).read_text())
        assert d["settings"]["A_v"] == 1.0 and d["settings"]["run_ps"] == 600.0
        assert [e["material"] for e in d["ensembles"]] == ["paper", "cg"]
        for e in d["ensembles"]:
            assert [r["seed"] for r in e["runs"]] == list(range(1, 21))
            assert e["box_length_A"] == pytest.approx(e["Gamma03"] * WK.L * WK.U.ell_A, rel=1e-12)
            for r in e["runs"]:          # every run kept its box (the projection converges to ~1e-5)
                assert r["box_length_A"] == pytest.approx(e["box_length_A"], rel=5e-5)   # 0.03 A
    mj = json.loads((ROOT / "results/main_job.json").read_text())
    table = WK.table([str(ROOT / p) for p in RESULT_FILES], mj["md_phase_speed_A_per_ps"],
                     mj["md_phase_speed_err_A_per_ps"], WK.MD_AMPLITUDE_A)
    doc = (ROOT / "docs/results.md").read_text()
    for row in table.splitlines():
        assert row in doc, row


def test_the_prose_quotes_the_5pN_ensembles():
    """docs/results.md's sentences about the 5-pN ensembles, formatted from the result files."""
    cold = {c["material"]: c for c in json.loads((ROOT / RESULT_FILES[0]).read_text())["cold"]}
    ens = {e["material"]: e for e in json.loads((ROOT / RESULT_FILES[1]).read_text())["ensembles"]}
    md_speed = json.loads((ROOT / "results/main_job.json").read_text())["md_phase_speed_A_per_ps"]

    def col(e, key):
        return np.array([r[key] for r in e["runs"]], float)

    p, g = ens["paper"], ens["cg"]
    sp, am, gs = col(p, "speed_A_per_ps"), col(p, "mode_amplitude_A"), col(g, "speed_A_per_ps")
    fk = {m: e["summary"]["kicked_tension_mean_pN"] for m, e in ens.items()}
    fe = {m: e["summary"]["equilibrium_tension_pN"] for m, e in ens.items()}
    c = WK.iso_constants(WK.material("cg"))
    slack_cg = slack_tension(WK.L, 158, WK.U.kT_to_rod(300.0), c["B"], c["C1"], c["C3"]).exact * WK.FORCE_PN
    half = col(p, "equilibrium_tension_first_half_pN")
    quotes = [
        f"from {half.mean():.1f} +- {half.std(ddof=1) / math.sqrt(len(half)):.1f} to {fe['paper']['mean']:.1f} +- "
        f"{fe['paper']['sem']:.1f} pN",
        f"{p['box_length_A']:.1f} A (paper) and {g['box_length_A']:.1f} A (coarse-grained)",
        f"{slack_cg:.1f} pN (this coarse-grained material)",
        f"{sp.mean():.2f} +- {sp.std(ddof=1):.2f} A/ps (mean +- sd over 20 seeds) and {am.mean():.1f} +- "
        f"{am.std(ddof=1):.1f} A, against {cold['paper']['speed_A_per_ps']:.3f} A/ps and "
        f"{cold['paper']['mode_amplitude_A']:.1f} A at 0 K",
        f"{np.sum(sp < md_speed)} of 20 runs are slower and {np.sum(am < WK.MD_AMPLITUDE_A)} of 20 are smaller",
        f"{fk['paper']['mean']:.1f} +- {fk['paper']['sd']:.1f} pN against the MD's 31 +- 8, and "
        f"{cold['paper']['kicked_tension_mean_pN']:.1f} for the 0-K rod",
        f"in all 20 runs ({gs.mean():.2f} +- {gs.std(ddof=1):.2f} A/ps)",
        f"({fk['cg']['mean']:.1f} +- {fk['cg']['sd']:.1f} pN)",
        f"already slower at 0 K ({cold['cg']['speed_A_per_ps']:.3f} A/ps)",
        f"scatters by {sp.std(ddof=1):.2f} A/ps (sd)",
        f"median of {np.median(col(p, 'speed_err_A_per_ps')):.2f} A/ps",
        f"{p['summary']['refused']} of the 20 warm records fail",
        f"{fe['paper']['mean']:.1f} +- {fe['paper']['sem']:.1f} pN (paper) and {fe['cg']['mean']:.1f} +- "
        f"{fe['cg']['sem']:.1f} pN (coarse-grained)",
    ]
    assert np.all(gs < md_speed)
    doc = re.sub(r"\s+", " ", (ROOT / "docs/results.md").read_text())
    assert [q for q in quotes if q not in doc] == []


def test_the_prose_quotes_the_38pN_ensembles():
    ens = {e["material"]: e for e in json.loads((ROOT / RESULT_FILES[2]).read_text())["ensembles"]}
    md_speed = json.loads((ROOT / "results/main_job.json").read_text())["md_phase_speed_A_per_ps"]
    out = {}
    for m, e in ens.items():
        runs = [r for r in e["runs"] if r["omega_per_ps"] is not None and math.isfinite(r["omega_per_ps"])]
        sp = np.array([r["speed_A_per_ps"] for r in runs])
        am = np.array([r["mode_amplitude_A"] for r in runs])
        out[m] = (e["summary"]["equilibrium_tension_pN"]["mean"], sp, am, e["summary"]["kicked_tension_mean_pN"])
    (Fp, sp, _, kp), (Fg, sg, ag, kg) = out["paper"], out["cg"]
    half = np.array([r["equilibrium_tension_first_half_pN"] for r in ens["paper"]["runs"]])
    sem = ens["paper"]["summary"]["equilibrium_tension_pN"]["sem"]
    quotes = [
        f"from {half.mean():.1f} +- {half.std(ddof=1) / math.sqrt(len(half)):.1f} to {Fp:.1f} +- {sem:.1f} pN",
        f"paper rod at {Fp:.1f} pN is faster ({sp.mean():.2f} +- {sp.std(ddof=1):.2f} A/ps; "
        f"{np.sum(sp < md_speed)} of 20 runs slower than the MD) and pulls {kp['mean']:.1f} +- {kp['sd']:.1f} pN",
        f"coarse-grained rod at {Fg:.1f} pN",
        f"({sg.mean():.2f} +- {sg.std(ddof=1):.2f} A/ps; {np.sum(sg < md_speed)} of {len(sg)} runs slower) and pulls "
        f"{kg['mean']:.1f} +- {kg['sd']:.1f} pN",
        f"smaller than the MD's in all {len(ag)} runs ({ag.mean():.1f} +- {ag.std(ddof=1):.1f} A)",
    ]
    assert np.all(ag < WK.MD_AMPLITUDE_A)
    doc = re.sub(r"\s+", " ", (ROOT / "docs/results.md").read_text())
    assert [q for q in quotes if q not in doc] == []
