"""results.json and report entries of the coarse-graining loop (workflows/steps/cgloop.py):
the rod with the paper's constants, the uniform coarse-grained rod (the prediction) and
the kicked MD (the measurement), side by side, each with its error. Keys:
docs/coarse-graining.md, "The loop: results.json keys"."""
from __future__ import annotations

import html
import json
import math
from pathlib import Path

import numpy as np

from dnarod.report.values import mean_over_seeds, number


def collect(cfg: dict, out: Path) -> dict:
    """{seed: cgrod/seed*/analysis.json} of the seeds whose loop ran."""
    found = {}
    for s in cfg["seeds"]:
        p = out / "cgrod" / f"seed{int(s)}" / "analysis.json"
        if p.is_file():
            found[int(s)] = json.loads(p.read_text())
    return found


def results(cfg: dict, runs: dict, res: dict) -> dict:
    """The top-level keys (always present, NaN with the reason when the loop did not run)."""
    cg = cfg.get("coarse_grain", {}) or {}
    on = bool(cg.get("enabled", True)) and 0.0 in [float(a) for a in cfg["A_v_A_per_ps"]] \
        and cfg.get("md", {}).get("enabled", True)
    rows = [runs[s] for s in sorted(runs)]
    sp, er = mean_over_seeds([r.get("speed_A_per_ps") for r in rows], [r.get("speed_err_A_per_ps") for r in rows])
    d = [r.get("dispersion") or {} for r in rows]
    dsp, der = mean_over_seeds([x.get("speed_A_per_ps") for x in d], [x.get("speed_err_A_per_ps") for x in d])
    reasons = sorted({r["reason"] for r in rows
                      if r.get("reason") and not math.isfinite(number(r.get("speed_A_per_ps")))})
    if on and not rows:
        reasons = ["no coarse-grained rod run found (cgrod/seed*/analysis.json)"]
    if not on:
        reasons = ["the loop needs an A_v = 0 MD run (A_v_A_per_ps must hold 0) and coarse_grain.enabled"]
    out = {
        "cg_rod_wave_speed_A_per_ps": sp,
        "cg_rod_wave_speed_err_A_per_ps": er,
        "cg_rod_dispersion_speed_A_per_ps": dsp,
        "cg_rod_dispersion_speed_err_A_per_ps": der,
        "cg_rod_planarity": float(np.mean([number(r.get("planarity")) for r in rows])) if rows else float("nan"),
        "cg_rod_quantity": next((r.get("quantity") for r in rows if r.get("quantity")), None),
        "cg_rod_reason": "; ".join(reasons) or None,
        "cg_rod": {"seeds": sorted(runs), "runs": rows, "m": cg.get("m"),
                   "replicas": cg.get("replicas", 20),
                   "definition": "prediction: the uniform coarse-grained rod (the long-wavelength stiffness "
                                 "K(q -> 0) of the step parameters of each seed's A_v = 0 MD, or the m-step "
                                 "compliance average when m is set, mapped by mdbridge.rod.material.steps_to_rod) "
                                 "run with the headline scene (same kick, length, shape and analysis as the "
                                 "paper-constant rod); error: spread over rod runs with the coarse-graining's "
                                 "bootstrap-replicate materials (+ the central fit error and the material's "
                                 "extrapolation and opening-rule parts), then combined over seeds like the MD",
                   "dispersion_definition": "Eq 39 (mdbridge/analysis/dispersion.py) with the coarse-grained "
                                            "material's shear and bend compliances averaged over the two "
                                            "transverse directions (inertia averaged), rho as measured; error "
                                            "over all bootstrap replicates (+ extrapolation and opening rule)"},
    }
    # the same keys whatever ran (NaN where a number is missing): runs stay comparable
    md, rod = number(res.get("md_wave_speed_A_per_ps")), number(res.get("rod_wave_speed_A_per_ps"))
    e = math.hypot(er, number(res.get("md_wave_speed_err_A_per_ps")))
    out["cg_rod_minus_md_A_per_ps"] = {"value": sp - md, "err": e,
                                       "z": (sp - md) / e if e > 0 else float("nan")}
    out["cg_rod_over_paper_rod"] = sp / rod if rod else float("nan")
    return out


def html_section(res: dict) -> str:
    def f(x, nd=3):
        x = number(x)
        return "n/a" if not math.isfinite(x) else f"{x:.{nd}g}"

    def pm(v, e):
        return f"{f(v)} &plusmn; {f(e, 2)}"

    reason = res.get("cg_rod_reason")
    rows = [("rod, paper's constants", pm(res.get("rod_wave_speed_A_per_ps"), res.get("rod_wave_speed_err_A_per_ps")),
             f(res.get("rod_dispersion_speed_A_per_ps"))),
            ("<b>predicted (CG rod)</b>",
             pm(res.get("cg_rod_wave_speed_A_per_ps"), res.get("cg_rod_wave_speed_err_A_per_ps"))
             + (f" ({html.escape(reason)})" if reason else ""),
             pm(res.get("cg_rod_dispersion_speed_A_per_ps"), res.get("cg_rod_dispersion_speed_err_A_per_ps"))),
            ("<b>measured (MD)</b>", pm(res.get("md_wave_speed_A_per_ps"), res.get("md_wave_speed_err_A_per_ps")), "-")]
    z = (res.get("cg_rod_minus_md_A_per_ps") or {}).get("z")
    return ("<h2>Prediction: the coarse-grained rod against the MD</h2>"
            "<p>The rod with the material coarse-grained from the unkicked (A_v = 0) MD, run with the headline kick "
            "and analysed like the paper-constant rod; its error comes from the coarse-grained parameters "
            "(rod runs over bootstrap-replicate materials). docs/coarse-graining.md, \"The loop\".</p>"
            "<table id=\"prediction\"><tr><th>model</th><th>speed at the headline A_v [A/ps]</th>"
            "<th>Eq 39, small amplitude [A/ps]</th></tr>"
            + "".join(f"<tr><td>{a}</td><td>{b}</td><td>{c}</td></tr>" for a, b, c in rows)
            + "</table>" + (f"<p>CG rod - MD: z = {f(z, 2)}</p>" if z is not None else ""))


def figure(res: dict):
    """Three speeds with their errors, and the two Eq 39 limits; None when nothing to show."""
    vals = [("rod (paper)", res.get("rod_wave_speed_A_per_ps"), res.get("rod_wave_speed_err_A_per_ps")),
            ("CG rod (predicted)", res.get("cg_rod_wave_speed_A_per_ps"), res.get("cg_rod_wave_speed_err_A_per_ps")),
            ("MD (measured)", res.get("md_wave_speed_A_per_ps"), res.get("md_wave_speed_err_A_per_ps"))]
    if not any(math.isfinite(number(v)) for _, v, _ in vals):
        return None
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 3.6))
    for i, (name, v, e) in enumerate(vals):
        if math.isfinite(number(v)):
            ax.errorbar([i], [number(v)], yerr=[number(e) if math.isfinite(number(e)) else 0.0], fmt="os"[i % 2],
                        capsize=4, color=f"C{i}")
    for name, v, ls in (("Eq 39, paper's D", res.get("rod_dispersion_speed_A_per_ps"), ":"),
                        ("Eq 39, CG material", res.get("cg_rod_dispersion_speed_A_per_ps"), "--")):
        if math.isfinite(number(v)):
            ax.axhline(number(v), color="k", ls=ls, lw=0.8, label=name)
    ax.set_xticks(range(3), [n for n, _, _ in vals])
    ax.set(xlabel="model [MD, paper rod, coarse-grained rod]", ylabel="speed [A/ps]",
           title=f"A_v = {number(res.get('headline_A_v_A_per_ps')):g} A/ps")
    ax.legend(fontsize=7)
    return fig


CAPTION = ("Standing-mode speed at the headline A_v of the rod with the paper's constants, the rod with the "
           "material coarse-grained from the unkicked MD (the prediction; error from the coarse-grained "
           "parameters) and the kicked MD (the measurement), with the small-amplitude limits of Eq 39. Look for "
           "whether the prediction's error bar reaches the MD's.")
