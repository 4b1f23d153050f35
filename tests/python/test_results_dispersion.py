"""The committed 158-bp MD dispersion (results/dispersion/, docs/dispersion.md).

The reduced results of the 5-ns thermostatted run are the one source of the numbers that
docs/dispersion.md quotes. Here: the prediction is recomputed from the committed modes.json
and tension.json by the workflow's own step (no trajectory needed) and equals the committed
prediction.json; the docs' quoted figures are those of that file; and the two independent
tensions (virial, and the linear rod fitted to the bend frequencies) agree, which is a
physical check of the mode analysis that could fail (control: the fit's T against a tension
5 pN off is rejected).
"""
import json
import math
import re
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
R = ROOT / "results" / "dispersion"
# the prose wraps lines anywhere: the quotes are matched with every run of whitespace as one space
DOC = re.sub(r"\s+", " ", (ROOT / "docs" / "dispersion.md").read_text())
RESULTS_DOC = re.sub(r"\s+", " ", (ROOT / "docs" / "results.md").read_text())   # the seeds and the stretched boxes


@pytest.fixture(scope="module")
def pred():
    return json.loads((R / "prediction.json").read_text())


def rows(pred, kind, rod="paper_rod", nmin=1):
    """The modes of KIND both the MD and ROD give a frequency for."""
    return [r for r in pred["rows"] if r["kind"] == kind and r["n"] >= nmin
            and r["md_omega0_per_ps"] is not None and r.get(f"{rod}_omega_per_ps") is not None]


def ratios(pred, kind, rod="paper_rod", nmin=1):
    """[(MD omega / ROD omega, z)] of those modes."""
    return [(r["md_omega0_per_ps"] / r[f"{rod}_omega_per_ps"], r[f"z_{rod}"]) for r in rows(pred, kind, rod, nmin)]


def test_prediction_recomputes_from_the_committed_modes(tmp_path, pred):
    out = tmp_path / "prediction.json"
    r = subprocess.run([sys.executable, "-m", "dnarod.steps.dispersion", "predict", str(R / "modes.json"),
                        "-o", str(out), "--tension", str(R / "tension.json"), "--n-fit-max", "4"],
                       capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    new = json.loads(out.read_text())
    for a, b in zip(new["rows"], pred["rows"]):
        assert (a["kind"], a["n"]) == (b["kind"], b["n"])
        for key in ("md_omega0_per_ps", "paper_rod_omega_per_ps", "z_paper_rod"):
            if b.get(key) is None:
                assert a.get(key) is None
            else:
                assert a[key] == pytest.approx(b[key], rel=1e-9)


def test_the_series_holds_the_whole_run():
    z = np.load(R / "mode_series.npz")
    t = next(z[k] for k in z.files if "time" in k)
    assert t.max() - t.min() == pytest.approx(5000.0, abs=1.0)


def test_docs_quote_the_committed_numbers(pred):
    T = pred["tension"]
    dyn = pred["fit"]["dynamics"]
    assert f"virial gives {T['tension_pN']:.1f} +- {T['tension_err_pN']:.1f} pN" in DOC
    assert f"T = {dyn['tension_pN']:.1f} +- {dyn['tension_err_pN']:.1f} pN" in DOC
    assert f"B = {dyn['B_pN_nm2']:.0f} +- {dyn['B_err_pN_nm2']:.0f} pN nm^2" in DOC
    assert f"chi2 {dyn['chi2']:.1f} for {dyn['dof']} dof" in DOC
    bend = {r["n"]: r for r in rows(pred, "bend")}
    ratio = {n: r["md_omega0_per_ps"] / r["paper_rod_omega_per_ps"] for n, r in bend.items()}
    z = {n: r["z_paper_rod"] for n, r in bend.items()}
    lo = (1, 2, 3)
    assert all(1.04 <= ratio[n] <= 1.05 + 5e-4 for n in lo)
    assert "within 1.4-1.7 combined errors" in DOC
    assert f"{min(z[n] for n in lo):.1f}" == "1.4" and f"{max(z[n] for n in lo):.1f}" == "1.7"
    mid = [n for n in bend if 4 <= n <= 10]
    assert 1.035 <= min(ratio[n] for n in mid) and max(ratio[n] for n in mid) <= 1.075
    assert f"z {min(z[n] for n in mid):.1f}-{max(z[n] for n in mid):.1f}" in DOC
    for kind, text in (("twist", "twist n = 1-6 by"), ("stretch", "stretch n = 1-5 by")):
        r = [q for q, _ in ratios(pred, kind)]
        m = re.search(re.escape(text) + r"\s+([\d.]+)-([\d.]+)x", DOC)
        assert m and float(m.group(1)) == pytest.approx(min(r), abs=0.005)
        assert float(m.group(2)) == pytest.approx(max(r), abs=0.005)
    modes = json.loads((R / "modes.json").read_text())
    d = modes["drift"]["bend"]
    assert f"+{100 * d['relative_shift']:.1f} +- {100 * d['relative_shift_err']:.1f} %" in DOC
    assert f"Birge ratio {d['birge_ratio']:.1f}" in DOC
    halves = modes["realisations"][0]["open_fraction"]["halves"]
    assert f"rises {halves[0]:.2f} -> {halves[1]:.2f}" in DOC
    refused = [m["n"] for m in modes["modes"] if m["kind"] == "bend" and (m["reason"] or "").startswith("not stat")]
    assert "bend n = " + ", ".join(map(str, refused)) + " are refused as not stationary" in DOC


def test_two_tensions_agree_and_a_wrong_one_does_not(pred):
    """The virial (GROMACS's pressure tensor) and the bend dynamics (the linear rod fitted to
    the MD's mode frequencies) are independent measurements of the same tension."""
    T, dyn = pred["tension"], pred["fit"]["dynamics"]

    def z(t_virial):
        return (dyn["tension_pN"] - t_virial) / np.hypot(dyn["tension_err_pN"], T["tension_err_pN"])

    assert abs(z(T["tension_pN"])) < 2.0
    assert abs(z(T["tension_pN"] - 5.0)) > 2.0 and abs(z(T["tension_pN"] + 10.0)) > 2.0   # controls


def test_thermostat_and_time_step_invariance_as_quoted():
    """docs/md.md: NVE and 1 fs against the 2-fs v-rescale run, bend n = 3-14 pooled."""
    inv = json.loads((R / "invariance.json").read_text())
    doc = re.sub(r"\s+", " ", (ROOT / "docs" / "md.md").read_text()).replace("\\|", "|")   # a table cell escapes |z|
    # pooled by the invariance step (workflows/steps/dispersion.py, tested on a known shift)
    p = inv["pooled_bend_n3"]["nve"]
    assert f"+{100 * p['mean']:.2f} +- {100 * p['err']:.2f} % (chi2 {p['chi2']:.1f} for {p['dof']} dof)" in doc
    assert abs(p["mean"]) < 2 * p["err"] and p["err"] < 0.01
    assert p["max_abs_z"] < 1.65
    p = inv["pooled_bend_n3"]["dt1fs"]
    assert (f"+{100 * p['mean']:.2f} +- {100 * p['err']:.2f} % (chi2 {p['chi2']:.1f} for {p['dof']} dof, "
            f"largest |z| {p['max_abs_z']:.1f})") in doc
    assert p["err"] < 0.01 and abs(p["mean"]) > 2.5 * p["err"]   # measured to 1 %, and not zero: said so


def test_provisional_coarse_grained_rod_as_quoted():
    """docs/dispersion.md: the ratios MD / coarse-grained rod of the provisional material."""
    p = json.loads((R / "cg_provisional" / "prediction.json").read_text())
    cg = json.loads((R / "cg_provisional" / "cg.json").read_text())
    assert cg["ok"]

    tw, st, b = (ratios(p, k, "cg_rod", nmin) for k, nmin in (("twist", 1), ("stretch", 1), ("bend", 2)))
    assert f"twist is {min(r for r, _ in tw):.2f}-{max(r for r, _ in tw):.2f}x" in DOC
    assert f"stretch {min(r for r, _ in st):.2f}-{max(r for r, _ in st):.2f}x faster" in DOC
    assert (f"bend n = 2-14 {min(r for r, _ in b):.2f}-{max(r for r, _ in b):.2f}x "
            f"(z {min(z for _, z in b):.1f}-{max(z for _, z in b):.1f})") in re.sub(r"\s+", " ", DOC)


def test_the_workflow_reproduces_the_committed_prediction(pred):
    """`dnarod compare --config workflows/config/dispersion.yaml` run end to end on the 5-ns MD
    (docs/dispersion.md, "Adopting a run made outside the workflow") reads the trajectory itself;
    the committed prediction.json came from the mode series (float32 amplitudes) by the steps
    run by hand. The same modes are refused, and every frequency agrees to 1e-5. The one
    allowed difference is a stationarity verdict at its threshold: a half-record fit of a
    wandering peak moves within its error with the amplitudes' rounding (docs/modes.md,
    "The common background"), so a refusal at halves z <= 3.1 may pass on the
    other side (bend n = 8: 3.02 from the series, 2.52 from the trajectory)."""
    wf = json.loads((R / "workflow" / "dispersion.json").read_text())
    rows = {(r["kind"], r["n"]): r for r in wf["rows"]}

    def at_threshold(reason):
        m = re.match(r"not stationary: the halves' frequencies differ by ([\d.]+) of", reason or "")
        return m is not None and float(m.group(1)) <= 3.1

    flipped = []
    for r in pred["rows"]:
        w = rows[(r["kind"], r["n"])]
        if (w["md_reason"] is None) != (r["md_reason"] is None):
            assert at_threshold(w["md_reason"]) or at_threshold(r["md_reason"]), (r["kind"], r["n"])
            flipped.append((r["kind"], r["n"]))
            continue
        for key in ("md_omega0_per_ps", "paper_rod_omega_per_ps"):
            if r[key] is not None:
                assert w[key] == pytest.approx(r[key], rel=1e-5), (r["kind"], r["n"], key)
    assert flipped == [("bend", 8)]
    assert wf["tension"]["tension_pN"] == pytest.approx(pred["tension"]["tension_pN"], rel=1e-9)
    assert "refused" in wf["cg_rod_reason"] and "21.9 independent samples" in wf["cg_rod_reason"]


def test_rod_at_300K_shifts_as_quoted():
    """docs/dispersion.md: the paper's rod at 300 K through `dnarod modes`, relative to the
    zero-tension linear dispersion (tests/python/test_modes_cold_rod.py's reference). Every
    axial mode that passes lies within 0.7 % of it at n >= 2 (a wrong peak, as the analysis
    once accepted, lies 40-83 % off: tests/python/test_modes_background.py)."""
    from test_modes_cold_rod import linear_omega_per_ps
    modes = json.loads((R / "rod_300K" / "modes.json").read_text())["modes"]
    shift = {(m["kind"], m["n"]): 100 * (m["omega_per_ps"] / linear_omega_per_ps(m["kind"], m["n"]) - 1)
             for m in modes if m["omega_per_ps"]}

    bend48 = [shift[("bend", n)] for n in range(4, 9)]
    quoted = (f"bend n = 1 +{shift[('bend', 1)]:.0f} %, n = 2 +{shift[('bend', 2)]:.0f} %, n = 4-8 "
              f"+{max(bend48):.0f} % down to +{min(bend48):.1f} %",
              "read the 300-K axial shifts at n >= 2 as under 0.7 %")
    doc = re.sub(r"\s+", " ", DOC)
    for q in quoted:
        assert q in doc, q
    assert ("bend", 3) not in shift
    assert all(abs(v) < 0.7 for (k, n), v in shift.items() if k != "bend" and n >= 2)


def test_statics_as_quoted(pred):
    """docs/dispersion.md, "The statics": the fit of T and B to the oscillator variances, its z
    against the virial tension and the dynamics' B, the per-mode ratios to the dynamics rod
    (n = 4-7 equal it within 1.00-1.04), and the refusal of the fit to the whole variances."""
    fit = pred["fit"]
    st = fit["statics"]
    assert f"T = {st['tension_pN']:.1f} +- {st['tension_err_pN']:.1f} pN and B = {st['B_pN_nm2']:.0f} +- " \
           f"{st['B_err_pN_nm2']:.0f} pN nm^2" in DOC
    assert f"(correlation {st['correlation_T_B']:.2f}; chi2 {st['chi2']:.2f} for {st['dof']} dof)" in DOC
    assert f"T is {fit['z_T_statics_vs_virial']:.1f} errors above the virial tension, B " \
           f"{fit['z_B_dynamics_vs_statics']:.1f}" in DOC
    assert fit["statics_total_variance"]["reason"].startswith("B runs to 0.001")
    ratio = {r["n"]: r for r in fit["statics_over_dynamics_rod"]}
    cells = " | ".join(f"{ratio[n]['ratio']:.2f} +- {ratio[n]['ratio_err']:.2f}" for n in sorted(ratio))
    assert f"| oscillator / dynamics rod | {cells} |" in DOC
    mid = [ratio[n]["ratio"] for n in (4, 6, 7)]
    assert 0.985 <= min(mid) and max(mid) < 1.045
    assert all(abs(ratio[n]["ratio"] - 1) < 2 * ratio[n]["ratio_err"] for n in (4, 6, 7))


def test_second_seed_as_quoted():
    """docs/results.md, "A second seed": the chi2 of the seed-to-seed differences per kind
    (twist and stretch covered by their errors, bend not), bend n = 1's shift against the
    string's omega^2 ~ T + B k^2 at the two seeds' virial tensions (agrees within the
    tensions' errors; control: equal tensions, which a -22 % shift at z -4.4 refutes), and
    the tensions quoted."""
    S = R / "seed2"
    d = json.loads((S / "seeds.json").read_text())
    diffs = {}
    for r in d["rows"]:
        a, b = r.get("seed1_omega_per_ps"), r.get("seed2_omega_per_ps")
        if a and b:
            z = (b - a) / math.hypot(r["seed1_omega_err_per_ps"], r["seed2_omega_err_per_ps"])
            diffs[(r["kind"], r["n"])] = (b / a - 1, z)
    chi2 = {k: sum(z ** 2 for (kind, _), (_, z) in diffs.items() if kind == k) for k in ("bend", "twist", "stretch")}
    dof = {k: sum(1 for kind, _ in diffs if kind == k) for k in chi2}
    for k in chi2:        # the invariance step's summary, which the README's headline reads
        assert d["differences_by_kind"]["seed2"][k]["chi2"] == pytest.approx(chi2[k], rel=1e-12)
        assert d["differences_by_kind"]["seed2"][k]["dof"] == dof[k]
    assert f"| twist | n = 1-6 | {chi2['twist']:.1f} for {dof['twist']} |" in RESULTS_DOC
    assert f"| stretch | n = 2-5 | {chi2['stretch']:.1f} for {dof['stretch']} |" in RESULTS_DOC
    assert f"| {chi2['bend']:.1f} for {dof['bend']} |" in RESULTS_DOC
    from scipy.stats import chi2 as chi2_dist
    assert chi2_dist.sf(chi2["twist"], dof["twist"]) > 0.05 and chi2_dist.sf(chi2["stretch"], dof["stretch"]) > 0.05
    assert chi2_dist.sf(chi2["bend"], dof["bend"]) < 1e-6
    assert f"about {math.sqrt(chi2['bend'] / dof['bend']):.1f}x too small" in RESULTS_DOC
    t1 = json.loads((R / "tension.json").read_text())["halves"]["first"]      # 1000-3000 ps of seed 1
    t2 = json.loads((S / "tension.json").read_text())
    assert f"Seed 2 holds {t2['tension_pN']:.1f} +- {t2['tension_err_pN']:.1f} pN" in RESULTS_DOC
    assert f"seed 1 held {t1:.1f} pN" in RESULTS_DOC
    shift, z = diffs[("bend", 1)]
    assert f"its n = 1 is {-100 * shift:.1f} % lower (z {z:.1f})" in RESULTS_DOC
    B = json.loads((R / "prediction.json").read_text())["fit"]["dynamics"]["B_pN_nm2"]
    k_nm = 2 * math.pi / (json.loads((S / "modes_1000_3000.json").read_text())["length_A"] / 10)
    Bk2 = B * k_nm ** 2
    string = math.sqrt((t2["tension_pN"] + Bk2) / (t1 + Bk2)) - 1
    assert f"predicts {100 * string:.1f} %" in RESULTS_DOC and f"(B k^2 = {Bk2:.1f} pN at n = 1)" in RESULTS_DOC
    t1_err = json.loads((R / "tension.json").read_text())["tension_err_pN"] * math.sqrt(2)   # a half of 4 ns
    string_err = 0.5 * (1 + string) * math.hypot(t2["tension_err_pN"] / (t2["tension_pN"] + Bk2), t1_err / (t1 + Bk2))
    shift_err = abs(shift / z)
    assert abs(shift - string) < 2 * math.hypot(shift_err, string_err)
    assert abs(shift - 0.0) > 3 * shift_err                                     # control: equal tensions


def test_twist_inertia_from_kinetic_equipartition_as_quoted(pred):
    """docs/dispersion.md, "What moves the twist modes": the twist and stretch modes'
    kinetic inertia (axial_inertia_table, recomputed here from modes.json) against the
    paper's and the atoms' own, and the twist stiffness it implies. The paper's I3 as the
    truth (the control) is rejected: the atoms' I33 is not."""
    from dna_models.units import Units
    from mdbridge.analysis.dispersion_prediction import Duplex, axial_inertia_table, paper_material
    modes = json.loads((R / "modes.json").read_text())
    ai = pred["fit"]["axial_inertia"]
    again = axial_inertia_table(modes["modes"], modes["n_bp"], modes["length_A"], pred["temperature_K"],
                                {"paper_rod": paper_material(Duplex(158, 15))})
    assert json.loads(json.dumps(again)) == ai
    doc = re.sub(r"\s+", " ", DOC)
    tw, st = ai["twist"]["pooled"], ai["stretch"]["pooled"]
    assert f"I3 = {tw['I3_rod_units'] / 2:.2f} +- {tw['I3_err_rod_units'] / 2:.2f} of the paper's" in doc
    assert f"(chi2 {tw['chi2']:.1f} for {tw['dof']} dof;" in doc
    I33 = json.loads((R / "cg_provisional" / "params.json").read_text())["rod"]["I_star"][2][2]
    z_atoms = (tw["I3_rod_units"] - I33) / tw["I3_err_rod_units"]
    z_paper = (tw["I3_rod_units"] - 2.0) / tw["I3_err_rod_units"]
    assert abs(z_atoms) < 1 and z_paper < -4                    # the control: the paper's I3 is rejected
    assert f"{tw['I3_rod_units'] / I33:.2f} +- {tw['I3_err_rod_units'] / I33:.2f} of the coarse-grained I33" in doc
    m2 = json.loads((R / "seed2" / "modes_1000_3000.json").read_text())
    tw2 = axial_inertia_table(m2["modes"], m2["n_bp"], m2["length_A"], pred["temperature_K"],
                              {"paper_rod": paper_material(Duplex(158, 15))})["twist"]["pooled"]
    assert (f"seed's 1000-3000 ps give {tw2['over_paper_rod']:.2f} +- {tw2['over_paper_rod_err']:.2f} "
            "(`seed2/modes_1000_3000.json`)") in doc
    assert abs(tw2["I3_rod_units"] - I33) < 2 * tw2["I3_err_rod_units"]
    u = Units.paper()
    D3_paper = u.D * u.D_ratios[2] * 1e30                        # pN nm^2
    # the stiffer twist by the atoms' own inertia (I33 over the paper's I3 = 2) and the MD's frequencies: D3 scales
    # as I3 omega^2, and the equipartition I3 is not used for it (omega0 cancels there)
    r = [r["md_omega0_per_ps"] / r["paper_rod_omega_per_ps"] for r in rows(pred, "twist")]
    f = [I33 / 2 * x ** 2 for x in r]
    assert (f"D3 = {I33 / 2:.2f} x ({min(r):.2f}-{max(r):.2f})^2, {min(f):.1f}-{max(f):.1f}x the paper's "
            f"{D3_paper:.0f} pN nm^2") in doc
    assert f"(chi2 {st['chi2']:.0f} for {st['dof']} dof;" in doc
    rho = [r["rho_rod_units"] for r in ai["stretch"]["modes"]]
    assert f"rho {min(rho):.2f}-{max(rho):.1f}x the paper's" in doc
    share = [m["oscillator_variance"] / m["variance"] for m in modes["modes"]
             if m["kind"] == "twist" and m["oscillator_variance"]]
    assert f"only {100 * min(share):.0f}-{100 * max(share):.0f} % of each twist mode's variance" in doc


def test_frequencies_against_tension_as_quoted(tmp_path):
    """docs/results.md, "Frequencies against tension": the series recomputed from the four
    committed predictions equals boxes/series.json, and the table and prose are its numbers."""
    from dna_models.units import Units
    B = R / "boxes"
    out = B / "series.json"
    rec = json.loads(out.read_text())
    r = subprocess.run([sys.executable, "-m", "dnarod.steps.dispersion", "series",
                        *[f"{x['name']}={ROOT / x['source']}" for x in rec["runs"]],
                        "-o", str(tmp_path / "s.json"), "--n",
                        *[str(m["n"]) for m in rec["modes"]], "--inertia-from",
                        str(R / "cg_provisional" / "params.json")], capture_output=True, text=True, timeout=300)
    assert r.returncode == 0, r.stderr
    again = json.loads((tmp_path / "s.json").read_text())
    for a, b in zip(again["modes"], rec["modes"]):
        assert a.get("slope") == pytest.approx(b.get("slope"), rel=1e-6) and a.get("reason") == b.get("reason")
    doc = re.sub(r"\s+", " ", RESULTS_DOC)
    runs = {x["name"]: x for x in rec["runs"]}
    for name, label in (("seed1", "seed 1, 1000-5000 ps"), ("seed2", "seed 2, 1000-3000 ps"),
                        ("box1.015", "+1.5 %, 500-1400 ps"), ("box1.03", "+3 %, 500-1400 ps")):
        x = runs[name]
        assert (f"| {label} | {x['length_A'] / runs['seed1']['length_A']:.3f} | {x['tension_pN']:.1f} +- "
                f"{x['tension_err_pN']:.1f} | {x['dynamics_tension_pN']:.1f} +- {x['dynamics_tension_err_pN']:.1f} | "
                f"{x['dynamics_B_pN_nm2']:.0f} |") in doc, name
    diffs = [runs[n]["dynamics_tension_pN"] - runs[n]["tension_pN"] for n in ("seed1", "seed2", "box1.015", "box1.03")]
    assert "virial's by " + ", ".join(f"{d:.1f}" for d in diffs[:3]) + f" and {diffs[3]:.1f} pN" in doc
    u = Units.paper()
    C3 = u.C * u.C_ratios[2] * 1e12
    assert f"stretch modulus ({C3:.0f} pN) would gain {0.015 * C3:.0f} and {0.03 * C3:.0f} pN" in doc
    ms = [m for m in rec["modes"] if m["reason"] is None]
    assert [m["n"] for m in ms] == [2, 3, 4, 5, 6]
    assert ("is " + ", ".join(f"{m['slope_over_predicted']:.2f}" for m in ms) + " at n = 2-6") in doc
    assert all(abs(m["z"]) < 2 for m in ms)
    assert f"z {min(m['z'] for m in ms):.1f} to {max(m['z'] for m in ms):.1f}" in doc
    runs_rec = json.loads((B / "runs.json").read_text())
    assert runs_rec["stopped_at_ps"] == 1400 and "**stopped at 1400 ps**" in doc
