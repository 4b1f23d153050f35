"""The comparison report: DIR/results.json and DIR/report/index.html (self-contained,
figures embedded as base64 PNG).

    python -m dnarod.report.report CONFIG.yaml OUT_DIR

Reads what the workflow's analysis steps wrote under OUT_DIR (rod/, md/, sweep/).
"""
from __future__ import annotations

import base64
import datetime
import html
import io
import json
import math
import sys
from pathlib import Path

import numpy as np

from mdbridge.md.gromacs.checks import DRIFT_TARGET_KJ_MOL_NS_ATOM as DRIFT_TARGET
from mdbridge.jsonio import write_json
from dnarod.report import dispersion, prediction, realisations, setting, verdict
from dnarod.report.values import mean_over_seeds, number
from dnarod.report.prediction import CAPTION as PREDICTION_CAPTION

PAPER_MD_RUN_PS = 600.0
PAPER = {"rod_wave_speed_A_per_ps": 1.4, "md_wave_speed_A_per_ps": 2.2, "md_run_ps": PAPER_MD_RUN_PS,
         "A_v_A_per_ps": [0.0, 1.0, 5.0], "source": "paper Sec 6.2"}


def fmt_av(av) -> str:
    """Run-folder label of a velocity amplitude: 1 -> '1', 0.5 -> '0.5'."""
    return f"{float(av):g}"


def _load(prefix: Path):
    j, z = prefix.with_suffix(".json"), prefix.with_suffix(".npz")
    if not j.is_file():
        return None, None
    return json.loads(j.read_text()), (dict(np.load(z)) if z.is_file() else None)


def rod_md_rmsd(rod_npz, md_npz):
    """Kabsch RMSD [A] of the rod's axis (interpolated in time) onto the MD axis, per MD frame."""
    from mdbridge.analysis import kabsch_rmsd
    tr, ar = rod_npz["times_ps"], rod_npz["axis"]
    tm, am = md_npz["times_ps"], md_npz["axis"]
    t_ok = tm[(tm >= tr[0]) & (tm <= tr[-1])]
    out = []
    for t in t_ok:
        j = int(np.clip(np.searchsorted(tr, t) - 1, 0, len(tr) - 2))
        f = (t - tr[j]) / (tr[j + 1] - tr[j])
        rod_axis = (1 - f) * ar[j] + f * ar[j + 1]
        out.append(kabsch_rmsd(rod_axis, am[list(tm).index(t)])[0])
    return t_ok, np.array(out)


def _check(j):
    """The cross-check speed of a run, NaN when the estimator flagged itself unreliable
    (a standing wave with too few periods in the record)."""
    if not j:
        return float("nan")
    if not j.get("wave_check", {}).get("reliable", True):
        return float("nan")
    return number(j.get("wave_speed_check_A_per_ps"))


def _png(fig) -> str:
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=90, bbox_inches="tight")
    import matplotlib.pyplot as plt
    plt.close(fig)
    return base64.b64encode(buf.getvalue()).decode("ascii")


def collect(cfg: dict, out: Path) -> dict:
    avs = [float(a) for a in cfg["A_v_A_per_ps"]]
    seeds = [int(s) for s in cfg["seeds"]]
    data: dict[str, dict] = {"rod": {}, "md": {}, "sweep": {}}
    for av in avs:
        data["rod"][av] = _load(out / "rod" / f"Av{fmt_av(av)}" / "analysis")
        if cfg.get("md", {}).get("enabled", True):
            for s in seeds:
                data["md"][(av, s)] = _load(out / "md" / f"Av{fmt_av(av)}_seed{s}" / "analysis")
    fit = out / "fit" / "modulus.json"
    data["modulus"] = json.loads(fit.read_text()) if fit.is_file() else None
    for av in cfg.get("sweep", {}).get("A_v_A_per_ps", []) or []:
        data["sweep"][float(av)] = _load(out / "sweep" / f"Av{fmt_av(av)}" / "analysis")
    data["md_setting"] = setting.collect(cfg, out) if cfg.get("md", {}).get("enabled", True) else {}
    data["cgrod"] = prediction.collect(cfg, out)
    data["dispersion"] = dispersion.collect(cfg, out)
    data["prestrain"] = {}
    for d in sorted((out / "prestrain").glob("Av*")) if (out / "prestrain").is_dir() else []:
        data["prestrain"][d.name] = _load(d / "analysis")
    return data


# What each number of results.json means (its "definitions").
DEFINITIONS = {
    "wave_speed": "NLS fit of forward+backward travelling waves to the k = 2 pi/L mode of u(s,t); "
                  "error: parametric bootstrap (fitted model + REML Ornstein-Uhlenbeck noise); "
                  "*_check: phase velocity of the mode; md_wave_speed_err_A_per_ps: with one seed, the one "
                  "record's error (md_wave_speed_err_one_record_A_per_ps) and the scatter between realisations "
                  "of this setting (md_wave_speed_realisations: its floor, from results/main_job_realisations.json; "
                  "workflows/report/realisations.py)",
    "md_energy_drift": "least-squares slope of the conserved energy from 10 % of the NVE "
                       "run to its end, per atom (mdbridge/md/gromacs/checks.py fit_drift); "
                       "worst headline run",
    "md_protocols": "equilibrated: v-rescale stage before the kick; paper: none "
                    "(mdbridge/md/gromacs/equilibrate.py)",
    "planarity": "RMS out-of-plane / RMS in-plane displacement over the run (0 = planar)",
    "md_bp_intact_fraction": "fraction of base pairs with N1-N3 < 3.5 A (minimum image), "
                             "last frame, mean over seeds",
    "md_setting": "per MD run folder, the setting every number of that run is of (medium, charges, held "
                  "pairs, tension) and its force field, from the run's build.json (workflows/report/setting.py)",
}


def _headline_md(cfg: dict, data: dict, head: float, seeds: list):
    """The headline amplitude's MD runs, their speed and error (the comparison's standing-mode
    fit when every run has one), the comparison block and its headline row."""
    from dnarod.report.comparison import comparison_block
    md_runs = [data["md"].get((head, s), (None, None))[0] for s in seeds]
    md_runs = [m for m in md_runs if m]
    md_speed, md_err = mean_over_seeds([m["wave_speed_A_per_ps"] for m in md_runs],
                                [m["wave_speed_err_A_per_ps"] for m in md_runs])
    comp = comparison_block(cfg, data)
    head_row: dict = next((r for r in comp["rows"] if r["A_v_A_per_ps"] == head), {})
    md_head = head_row.get("md") or {}
    if md_runs and all("standing_mode" in m for m in md_runs):
        # the three-part error of mdbridge/analysis/mode_error.py (offset always fitted)
        md_speed, md_err = md_head.get("speed_A_per_ps", md_speed), md_head.get("speed_err_A_per_ps", md_err)
    return md_runs, md_speed, md_err, comp, head_row, md_head


def _rmsd_per_seed(data: dict, head: float, seeds: list) -> list:
    """The rod's axis fitted onto each headline MD's, per MD frame (rod_md_rmsd)."""
    rmsd = []
    for s in seeds:
        r = data["rod"].get(head, (None, None))[1]
        m = data["md"].get((head, s), (None, None))[1]
        if r is not None and m is not None:
            t, d = rod_md_rmsd(r, m)
            if len(d):
                rmsd.append({"seed": s, "times_ps": t.tolist(), "rmsd_A": d.tolist()})
    return rmsd


def results_json(cfg: dict, data: dict) -> dict:
    from mdbridge.analysis.dispersion import bend_modulus_for_speed
    head = float(cfg.get("headline_A_v_A_per_ps", 1.0))
    seeds = [int(s) for s in cfg["seeds"]]
    rod_j, _ = data["rod"].get(head, (None, None))
    md_runs, md_speed, md_err, comp, head_row, md_head = _headline_md(cfg, data, head, seeds)
    # one record's error does not cover the scatter between runs of one setting: add the
    # floor measured from the committed realisations of this setting (realisations.py)
    floor = realisations.floor_for(cfg, len(md_runs)) if md_runs else {"floor_A_per_ps": None, "reason": "no MD"}
    md_err_record = md_err
    if floor["floor_A_per_ps"] is not None and math.isfinite(md_err):
        md_err = math.hypot(md_err, floor["floor_A_per_ps"])
        if md_head:     # the matched comparison's headline row states the same error
            md_head.update(speed_err_one_record_A_per_ps=md_head.get("speed_err_A_per_ps"),
                           speed_err_realisations_A_per_ps=floor["floor_A_per_ps"], speed_err_A_per_ps=md_err)
    res = {
        "headline_A_v_A_per_ps": head,
        "rod_wave_speed_A_per_ps": number(rod_j and rod_j["wave_speed_A_per_ps"]),
        "rod_wave_speed_err_A_per_ps": number(rod_j and rod_j["wave_speed_err_A_per_ps"]),
        "rod_wave_speed_check_A_per_ps": _check(rod_j),
        "rod_dispersion_speed_A_per_ps": number(rod_j and rod_j["dispersion"]["bend_branch_speed_A_per_ps"]),
        "md_wave_speed_A_per_ps": md_speed,
        "md_wave_speed_err_A_per_ps": md_err,
        "md_wave_speed_err_one_record_A_per_ps": md_err_record,
        "md_wave_speed_realisations": floor,
        "md_wave_speed_check_A_per_ps": mean_over_seeds([_check(m) for m in md_runs],
                                                 [0.0] * len(md_runs))[0] if md_runs else float("nan"),
        # the worst |drift| of the headline MD runs; target: DRIFT_TARGET (checks.py)
        "md_energy_drift_kJ_mol_per_ns_per_atom": max(
            (number(m.get("energy_drift_kJ_mol_per_ns_per_atom")) for m in md_runs), key=abs,
            default=float("nan")),
        "md_energy_drift_target_kJ_mol_per_ns_per_atom": DRIFT_TARGET,
        "md_protocols": sorted({m.get("protocol", "paper") for m in md_runs}),
        "rod_planarity": number(rod_j and rod_j["planarity"]),
        "md_planarity": float(np.mean([number(m["planarity"]) for m in md_runs])) if md_runs else float("nan"),
        "md_bp_intact_fraction": float(np.mean([m["bp_intact_fraction_final"] for m in md_runs]))
        if md_runs else float("nan"),
        "rod_run_ps": float(cfg["rod"]["run_ps"]),
        "md_run_ps": float({float(k): v for k, v in (cfg["md"].get("run_ps_per_A_v") or {}).items()}
                           .get(head, cfg["md"]["run_ps"])) if md_runs else 0.0,
        "seeds": seeds,
        "md_setting": data.get("md_setting", {}),
        "A_v_A_per_ps": [float(a) for a in cfg["A_v_A_per_ps"]],
        "paper": PAPER,
        "definitions": dict(DEFINITIONS),
        "comparison": comp,
        "md_wave_speed_err_parts_A_per_ps": {k: md_head.get(k) for k in (
            "speed_err_fit_A_per_ps", "speed_err_record_A_per_ps", "speed_err_seeds_A_per_ps",
            "speed_err_seeds_note", "speed_err_realisations_A_per_ps")} if md_head else None,
        "md_quantity": md_head.get("quantity"),
        "rod_quantity": (head_row.get("rod") or {}).get("quantity"),
        "md_regime": (head_row.get("md_regime") or {}).get("regime"),
        "rod_regime": (head_row.get("rod_regime") or {}).get("regime"),
        "runs": {"rod": [j for j, _ in data["rod"].values() if j],
                 "md": [j for j, _ in data["md"].values() if j],
                 "sweep": [j for j, _ in data["sweep"].values() if j]},
    }
    res.update(prediction.results(cfg, data.get("cgrod", {}), res))
    if rod_j and math.isfinite(md_speed):
        # Eq 39 inverted: only meaningful if the MD wave were small-amplitude (see modulus.py)
        res["bend_modulus_for_md_speed_small_amplitude"] = bend_modulus_for_speed(
            md_speed, rod_j["dispersion"]["fiducial_length"], rod_j["dispersion"]["Gamma03"])
    if data.get("modulus"):
        res["modulus_fit_for_md_speed"] = data["modulus"]
    disp = dispersion.results(cfg, data.get("dispersion", {}))
    if disp is not None:
        res["dispersion"] = disp
    rmsd = _rmsd_per_seed(data, head, seeds)
    res["rod_md_rmsd"] = rmsd
    res["rod_md_rmsd_A_final"] = float(np.mean([x["rmsd_A"][-1] for x in rmsd])) if rmsd else float("nan")
    return res


# What each figure shows and what to look for (the report prints it under the figure).
CAPTIONS = {
    "kymographs": "In-plane displacement u_in of the helical axis from the straight axis, over axial "
                  "position and time, for the rod and the MD at the headline amplitude. Look for the "
                  "same pattern and period: tilted stripes are a travelling wave, vertical nodes a "
                  "standing mode.",
    "snapshots": "u_in(s) at five times (cf. paper Figs 8-9). Look for the shape of the fundamental "
                 "mode and whether the MD curve is as smooth as the rod's (thermal noise in the MD).",
    "planarity_integrity": "Left: RMS out-of-plane over RMS in-plane displacement (0 = a planar "
                           "motion). Right: fraction of MD base pairs still paired (N1-N3 < 3.5 A). "
                           "Look for rod curves near 0 and MD integrity near 1; a falling integrity "
                           "means the duplex frays and its numbers mean less.",
    "rmsd": "RMSD of the rod's helical axis fitted onto the MD's (Kabsch), per MD frame. It starts "
            "near 0 (the MD is built on the rod); look for how fast the two drift apart.",
    "prediction": PREDICTION_CAPTION,
    "dispersion": dispersion.CAPTION,
    "amplitude": "Rod wave speed against the kick amplitude A_v (sweep), with the small-amplitude "
                 "limit of Eq 39, the paper's values and this run's MD. Look for where the rod leaves "
                 "the linear limit and where the MD point sits on the rod's curve.",
}


def figures(cfg: dict, data: dict, res: dict) -> dict:
    """The report's figures as matplotlib Figures, keyed like CAPTIONS."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    head = res["headline_A_v_A_per_ps"]
    seeds = res["seeds"]
    rod = data["rod"].get(head, (None, None))[1]
    md = next((data["md"][(head, s)][1] for s in seeds
               if data["md"].get((head, s), (None, None))[1] is not None), None)
    pairs = [("rod", rod)] + ([("MD", md)] if md is not None else [])
    figs = {}
    fig = dispersion.figure(res.get("dispersion"))
    if fig is not None:
        figs["dispersion"] = fig
    if rod is not None:     # the wave figures (no wave analyses: analysis.waves is false)
        figs.update({"kymographs": _kymographs(plt, pairs, head, True), "snapshots": _snapshots(plt, pairs),
                     "planarity_integrity": _planarity_integrity(plt, data)})
    if res["rod_md_rmsd"]:
        figs["rmsd"] = _rmsd_figure(plt, res["rod_md_rmsd"], head)
    fig = prediction.figure(res)
    if fig is not None:
        figs["prediction"] = fig
    sw = sorted((av, j) for av, (j, _) in data["sweep"].items() if j)
    if sw:
        figs["amplitude"] = _amplitude_figure(plt, sw, data)
    return figs


def _kymographs(plt, pairs, head, have_rod: bool):
    fig, axs = plt.subplots(1, len(pairs), figsize=(5.5 * len(pairs), 4), squeeze=False)
    vmax = max(np.max(np.abs(z["u_in"])) for _, z in pairs if z is not None) if have_rod else 1
    for ax, (name, z) in zip(axs[0], pairs):
        if z is None:
            continue
        im = ax.imshow(z["u_in"], aspect="auto", origin="lower", cmap="RdBu_r", vmin=-vmax, vmax=vmax,
                       extent=[z["x_A"][0], z["x_A"][-1], z["times_ps"][0], z["times_ps"][-1]])
        ax.set(xlabel="axial position s [A]", ylabel="t [ps]", title=f"{name}: u_in(s, t), A_v = {head:g} A/ps")
    fig.colorbar(im, ax=axs[0].tolist(), label="in-plane displacement [A]")
    return fig


def _snapshots(plt, pairs):
    """u_in(s) at five times (paper Figs 8-9)."""
    fig, axs = plt.subplots(len(pairs), 1, figsize=(8, 3 * len(pairs)), squeeze=False, constrained_layout=True)
    for ax, (name, z) in zip(axs[:, 0], pairs):
        if z is None:
            continue
        t_end = min(zz["times_ps"][-1] for _, zz in pairs if zz is not None)
        for tt in np.linspace(z["times_ps"][0], t_end, 5):
            i = int(np.argmin(np.abs(z["times_ps"] - tt)))
            ax.plot(z["x_A"], z["u_in"][i], label=f"t = {z['times_ps'][i]:.0f} ps")
        ax.set(xlabel="axial position s [A]", ylabel="u_in [A]", title=f"{name} snapshots (cf. paper Figs 8-9)")
        ax.legend(fontsize=7)
    return fig


def _planarity_integrity(plt, data):
    fig, axs = plt.subplots(1, 2, figsize=(11, 3.8))
    for av, (j, z) in data["rod"].items():
        if z is not None:
            axs[0].plot(z["times_ps"], z["ratio"], "-", label=f"rod A_v={av:g}")
    for (av, s), (j, z) in data["md"].items():
        if z is not None:
            axs[0].plot(z["times_ps"], z["ratio"], "--", label=f"MD A_v={av:g} seed {s}")
            axs[1].plot(z["intact_times_ps"], z["intact_fraction"], label=f"A_v={av:g} seed {s}")
    axs[0].set(xlabel="t [ps]", ylabel="RMS out-of-plane / in-plane [1]", title="planarity", yscale="log")
    axs[0].legend(fontsize=7)
    axs[1].set(xlabel="t [ps]", ylabel="fraction with N1-N3 < 3.5 A [1]", title="MD base-pair integrity", ylim=(0, 1.05))
    axs[1].legend(fontsize=7)
    return fig


def _rmsd_figure(plt, rmsd, head):
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for r in rmsd:
        ax.plot(r["times_ps"], r["rmsd_A"], label=f"seed {r['seed']}")
    ax.set(xlabel="t [ps]", ylabel="RMSD [A]", title=f"rod axis fitted onto MD axis (Kabsch), A_v = {head:g}")
    ax.legend(fontsize=7)
    return fig


def _amplitude_figure(plt, sw, data):
    """The wave speed against the amplitude: the rod's sweep, Eq 39, the paper's, the MD's."""
    fig, ax = plt.subplots(figsize=(6, 3.8))
    a = np.array([av for av, _ in sw])
    v = np.array([number(j["wave_speed_A_per_ps"]) for _, j in sw])
    e = np.array([number(j["wave_speed_err_A_per_ps"]) for _, j in sw])
    ax.errorbar(a, v, yerr=e, fmt="o-", label="rod (this run)")
    ax.axhline(sw[0][1]["dispersion"]["bend_branch_speed_A_per_ps"], color="k", ls=":",
               label="Eq 39, small amplitude (bend branch)")
    ax.axhline(PAPER["rod_wave_speed_A_per_ps"], color="C1", ls="--", label="paper rod 1.4 A/ps")
    ax.axhline(PAPER["md_wave_speed_A_per_ps"], color="C2", ls="--", label="paper MD 2.2 A/ps")
    mdv = [(av, number(j["wave_speed_A_per_ps"])) for (av, s), (j, _) in data["md"].items() if j]
    if mdv:
        ax.plot(*zip(*mdv), "s", color="C3", label="MD (this run)")
    pos = a[a > 0]
    ax.set_xscale("symlog", linthresh=float(pos.min()) if len(pos) else 1.0)
    ax.set(xlabel="A_v [A/ps]", ylabel="wave speed [A/ps]", title="wave speed vs amplitude")
    ax.legend(fontsize=7)
    return fig


def _f(x, nd=3):
    if x is None:
        return "n/a"
    try:
        x = float(x)
    except (TypeError, ValueError):
        return html.escape(str(x))
    return "n/a" if not math.isfinite(x) else f"{x:.{nd}g}"


def _drift_html(x) -> str:
    """The drift, marked when it exceeds the target (docs/md.md, energy conservation)."""
    if x is None or not math.isfinite(float(x)):
        return "n/a"
    if abs(float(x)) > DRIFT_TARGET:
        return (f'<span style="color:#b00"><b>{_f(x, 2)}</b> (over the target {DRIFT_TARGET:g}: '
                "energy not conserved well enough)</span>")
    return f"{_f(x, 2)} (target {DRIFT_TARGET:g})"


def _check_part(x, sep="; ") -> str:
    """'check X' + SEP for the summary, or nothing when the check gave no number (the
    table of all runs says why)."""
    return f"check {_f(x)}{sep}" if math.isfinite(number(x)) else ""


def _wave_sections(table, matched_html, runs) -> str:
    """The wave-speed part of the page: the summary against the paper, the matched comparison
    and every run."""
    return f"""<h2>Summary vs the paper</h2>
<table id="headline"><tr><th>quantity</th><th>this run</th><th>paper (Sec 6)</th></tr>{table}</table>
{matched_html}
<h2>All runs</h2>
<table><tr><th>kind</th><th>A_v [A/ps]</th><th>seed</th><th>speed [A/ps]</th><th>check</th>
<th>planarity</th><th>bp intact</th><th>energy drift [kJ/mol/ns/atom]</th><th>t_end [ps]</th><th>MD setting</th></tr>
{runs}</table>"""


def _not_measured(items: str) -> str:
    return f"""<h2 id="not-measured">Not measured or refused in this run</h2>
<ul id="not-measured-list">{items or "<li>nothing: every summary row has a number</li>"}</ul>"""


def write_html(cfg: dict, res: dict, figs: dict, path: Path):
    rows = [
        (f"rod {html.escape(res.get('rod_quantity') or 'wave speed')} [A/ps] ({html.escape(str(res.get('rod_regime')))})", f"{_f(res['rod_wave_speed_A_per_ps'])} &plusmn; {_f(res['rod_wave_speed_err_A_per_ps'], 2)}"
         f" ({_check_part(res['rod_wave_speed_check_A_per_ps'])}Eq 39: {_f(res['rod_dispersion_speed_A_per_ps'])})", "1.4"),
        (f"MD {html.escape(res.get('md_quantity') or 'wave speed')} [A/ps] ({html.escape(str(res.get('md_regime')))})", f"{_f(res['md_wave_speed_A_per_ps'])} &plusmn; {_f(res['md_wave_speed_err_A_per_ps'], 2)}"
         + (f" ({_check_part(res['md_wave_speed_check_A_per_ps'], '')})"
            if _check_part(res['md_wave_speed_check_A_per_ps']) else ""), "2.2 (by eye)"),
        ("predicted (CG rod) [A/ps]", f"{_f(res.get('cg_rod_wave_speed_A_per_ps'))} &plusmn; "
         f"{_f(res.get('cg_rod_wave_speed_err_A_per_ps'), 2)} (Eq 39: {_f(res.get('cg_rod_dispersion_speed_A_per_ps'))} "
         f"&plusmn; {_f(res.get('cg_rod_dispersion_speed_err_A_per_ps'), 2)})"
         + (f" ({html.escape(res['cg_rod_reason'])})" if res.get("cg_rod_reason") else ""), "-"),
        ("MD energy drift [kJ/mol/ns per atom]", _drift_html(res["md_energy_drift_kJ_mol_per_ns_per_atom"])
         + f" (protocol: {html.escape(', '.join(res['md_protocols']) or 'n/a')})", "not reported"),
        ("rod planarity (out/in RMS)", _f(res["rod_planarity"]), "planar"),
        ("MD planarity (out/in RMS)", _f(res["md_planarity"]), "planar (A_v = 1), non-planar (A_v = 5)"),
        ("MD base pairs intact, last frame", _f(res["md_bp_intact_fraction"]), "not reported"),
        ("rod-MD axis RMSD, last frame [A]", _f(res["rod_md_rmsd_A_final"]), "not reported"),
        ("rod D reproducing the MD speed (x paper D)", _f(((res.get("modulus_fit_for_md_speed") or {}).get("fits") or {}).get("bend", {}).get("scale")), "-"),
        ("rod C3 reproducing the MD speed (x paper C3)", _f(((res.get("modulus_fit_for_md_speed") or {}).get("fits") or {}).get("stretch", {}).get("scale")), "-"),
        ("rod / MD run length [ps]", f"{_f(res['rod_run_ps'])} / {_f(res['md_run_ps'])}", "? / 600"),
        ("seeds", ", ".join(map(str, res["seeds"])), "one run per A_v"),
    ]
    # rows with a number go into the summary; the others move below it, each with its reason
    have = [(a, b, c) for a, b, c in rows if not b.startswith("n/a")]
    missing = [(a, verdict.reason_missing(html.unescape(a), res)) for a, b, c in rows if b.startswith("n/a")]
    table = "\n".join(f"<tr><td>{a}</td><td>{b}</td><td>{c}</td></tr>" for a, b, c in have)
    not_measured = "\n".join(f"<li><b>{a}</b>: {html.escape(why)}</li>" for a, why in missing)
    runs = "\n".join(
        f"<tr><td>{j['kind']}</td><td>{_f(j.get('A_v_A_per_ps'))}</td><td>{j.get('seed', '')}</td>"
        f"<td>{_f(j['wave_speed_A_per_ps'])} &plusmn; {_f(j['wave_speed_err_A_per_ps'], 2)}"
        f"{' (' + html.escape(j['wave_fit']['reason']) + ')' if j.get('wave_fit', {}).get('reason') else ''}</td>"
        f"<td>{_f(_check(j))}{'' if j.get('wave_check', {}).get('reliable', True) else ' (' + html.escape(j['wave_check'].get('reason', '')) + ')'}</td><td>{_f(j['planarity'])}</td>"
        f"<td>{_f(j.get('bp_intact_fraction_final', ''))}</td>"
        f"<td>{_drift_html(j.get('energy_drift_kJ_mol_per_ns_per_atom')) if j['kind'] == 'md' else ''}</td>"
        f"<td>{_f(j['t_end_ps'])}"
        f"{'' if j.get('complete', True) else ' (stopped: ' + html.escape(j.get('stopped', '')) + ')'}</td>"
        f"<td>{html.escape(setting.of_run(res.get('md_setting', {}), j)) if j['kind'] == 'md' else ''}</td></tr>"
        for j in res["runs"]["rod"] + res["runs"]["md"] + res["runs"]["sweep"])
    from dnarod.report.comparison import html_table
    matched_html = html_table(res["comparison"]) if res.get("comparison") else ""
    # a refused prediction is said in the verdict and in the "not measured" list, not as a table of n/a
    if math.isfinite(number(res.get("cg_rod_wave_speed_A_per_ps"))):
        matched_html = prediction.html_section(res) + matched_html
    disp_html = dispersion.html_section(res.get("dispersion"))
    fig_html = {k: (f'<figure id="fig-{html.escape(k)}"><img alt="{html.escape(k)}" '
                    f'src="data:image/png;base64,{_png(fig)}"><figcaption><b>{html.escape(k)}.</b> '
                    f'{html.escape(CAPTIONS[k])}</figcaption></figure>') for k, fig in figs.items()}
    # the figure that shows the headline result comes first, right under the verdict
    lead = next((k for k in ("dispersion", "prediction", "kymographs") if k in fig_html), next(iter(fig_html), None))
    lead_html = fig_html.pop(lead) if lead is not None else ""
    imgs = "\n".join(fig_html.values())
    waves = bool(res["runs"]["rod"] or res["runs"]["md"])
    note = ""
    if waves and float(res["md_run_ps"]) < PAPER_MD_RUN_PS:
        note = (f"<p><b>Note:</b> the MD here runs {_f(res['md_run_ps'])} ps, shorter than the paper's "
                "600 ps, to fit the default configuration's time budget; use "
                "<code>--config workflows/config/paper.yaml</code> for the paper's length.</p>")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(f"""<!DOCTYPE html><html><head><meta charset="utf-8"><title>dnarod compare</title>
<style>body{{font-family:sans-serif;max-width:1100px;margin:auto}} td,th{{border:1px solid #ccc;padding:3px 8px}}
table{{border-collapse:collapse}} img{{max-width:100%}} figcaption{{font-size:90%;color:#333}}</style></head><body>
<h1>Rod vs all-atom MD: bend-shear wave on a periodic duplex</h1>
<section id="verdict"><h2>What this run found</h2><p>{" ".join(verdict.opening(res, waves))}</p></section>
{setting.html_section(res.get("md_setting", {}))}
{lead_html}{disp_html}{note}
{_wave_sections(table, matched_html, runs) if waves else
 "<p>No wave-speed analyses in this configuration (analysis.waves is false: no kicked run).</p>"}
<h2>Figures</h2>{imgs or "<p>(the figure above)</p>"}
{_not_measured(not_measured) if waves else ""}
<p>Generated {datetime.datetime.now(datetime.timezone.utc).isoformat(timespec='seconds')} by
<code>dnarod compare</code>. Headline run: A_v = {_f(res['headline_A_v_A_per_ps'])} A/ps.
Estimators and definitions: docs/analysis.md.</p>
</body></html>
""")


def main(argv=None) -> int:
    import yaml
    argv = sys.argv[1:] if argv is None else argv
    cfg = yaml.safe_load(Path(argv[0]).read_text())
    out = Path(argv[1])
    data = collect(cfg, out)
    res = results_json(cfg, data)
    write_json(out / "results.json", res)
    write_html(cfg, res, figures(cfg, data, res), out / "report" / "index.html")
    return 0


if __name__ == "__main__":
    sys.exit(main())
